"""Parse SysML v2 text with the textX grammar ``metamodel/grammar/sysml2.tx``.

The parse tree is made of textX objects whose classes are named after the grammar rules
(``Package``, ``Definition``, ``Usage``, ``MetadataUsage``...). The helpers below turn its
raw pieces (quoted names, string literals, comment bodies, multiplicities, literal
expressions) into plain Python values, so callers never handle textX details.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from functools import cache
from pathlib import Path
from typing import Any

from arpeggio import StrMatch
from textx import get_location, metamodel_from_file, metamodel_from_str
from textx.exceptions import TextXError, TextXSyntaxError

from earl_m2t.diagnostics import ModelReadError, SourceTextError
from earl_m2t.read.bounded import read_regular_bytes
from earl_m2t.resources import metamodel_path
from earl_m2t.sysml2.limits import MAX_TEXT_BYTES, Refused, line_and_column, refuse_unreadable, size_problem

__all__ = [
    "Sysml2SyntaxError",
    "parse_file",
    "parse_text",
    "location",
    "name_segments",
    "simple_name",
    "unquote_name",
    "identification",
    "doc_text",
    "multiplicity",
    "literal_value",
    "members",
    "rule",
    "unwrap",
]

GRAMMAR = ("grammar", "sysml2.tx")
MODEL_GRAMMAR = ("grammar", "sysml2-model.tx")
# The rule Element of a grammar file: from its first line to the line holding only ';'.
_ELEMENT_RULE = re.compile(r"^Element:\n.*?^;\n", re.MULTILINE | re.DOTALL)

# One segment of a qualified name: a quoted name or a basic name.
_SEGMENT = re.compile(r"'(?:[^'\\]|\\.)*'|[A-Za-z_][A-Za-z_0-9]*")
_ESCAPE = re.compile(r"\\(.)")
_MAX_EXPECTED = 16
_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "b": "\b", "f": "\f"}


class Sysml2SyntaxError(SourceTextError):
    """SysML v2 text that does not parse."""


@cache
def _metamodel() -> Any:
    return metamodel_from_file(str(metamodel_path(*GRAMMAR)), autokwd=True)


@cache
def _model_metamodel() -> Any:
    """The model grammar: sysml2.tx with the rule Element of sysml2-model.tx."""
    base = metamodel_path(*GRAMMAR).read_text(encoding="utf-8")
    wider = _ELEMENT_RULE.search(metamodel_path(*MODEL_GRAMMAR).read_text(encoding="utf-8"))
    if wider is None or _ELEMENT_RULE.search(base) is None:
        raise RuntimeError("the SysML v2 grammars have no rule Element")
    text = _ELEMENT_RULE.sub(lambda _: wider.group(0), base, count=1)
    return metamodel_from_str(text, autokwd=True)


def parse_text(text: str, file_name: str = "<text>", model: bool = False) -> Any:
    """Parse SysML v2 text and return the root namespace (rule ``RootNamespace``).

    ``model`` reads it with the model grammar, where constructs outside the subset are
    ``OutsideSubset`` nodes rather than syntax errors.
    """
    metamodel = _model_metamodel() if model else _metamodel()
    if len(text) > MAX_TEXT_BYTES // 4:  # fewer characters cannot make more bytes
        too_large = size_problem(len(text.encode("utf-8", "surrogatepass")))
        if too_large:
            raise Sysml2SyntaxError(file_name, 0, 0, f"{too_large}: not read")
    try:
        refuse_unreadable(text)
    except Refused as refused:
        line, column = line_and_column(text, refused.offset)
        raise Sysml2SyntaxError(file_name, line, column, refused.message) from None
    try:
        return metamodel.model_from_str(text, file_name=file_name)
    except TextXSyntaxError as error:
        raise Sysml2SyntaxError(
            file_name, error.line or 0, error.col or 0, _syntax_message(error, text)
        ) from None
    except TextXError as error:
        raise Sysml2SyntaxError(
            file_name, error.line or 0, error.col or 0, str(error.message)
        ) from None


def parse_file(path: Path, model: bool = False) -> Any:
    """Parse a SysML v2 file (UTF-8) and return its root namespace."""
    try:
        data = read_regular_bytes(path)
        too_large = size_problem(len(data))
        if too_large:
            raise Sysml2SyntaxError(str(path), 0, 0, f"{too_large}: not read")
        text = data.decode("utf-8")
    except ModelReadError as error:
        raise Sysml2SyntaxError(str(path), 0, 0, f"cannot read the file: {error.message}") from None
    except UnicodeDecodeError as error:
        line, column = _position(error.object, error.start)
        raise Sysml2SyntaxError(str(path), line, column, f"not UTF-8 text: {error.reason}") from None
    return parse_text(text, str(path), model)


def _position(data: bytes, offset: int) -> tuple[int, int]:
    """1-based line and column (in bytes) of a byte offset."""
    line_start = data.rfind(b"\n", 0, offset) + 1
    return data.count(b"\n", 0, offset) + 1, offset - line_start + 1


def _syntax_message(error: TextXSyntaxError, text: str) -> str:
    expected: list[str] = []
    for candidate in getattr(error, "expected_rules", None) or []:
        if isinstance(candidate, StrMatch):
            label = f"'{candidate.to_match}'"
        else:
            label = getattr(candidate, "rule_name", "") or str(candidate)
            if label.islower():  # a keyword (matched as a whole word)
                label = f"'{label}'"
        if label and label not in expected:
            expected.append(label)
    found = _found(text, error.line or 0, error.col or 0)
    if not expected:
        return f"syntax error at {found}"
    shown = ", ".join(expected[:_MAX_EXPECTED])
    more = ", ..." if len(expected) > _MAX_EXPECTED else ""
    return f"syntax error at {found}: expected {shown}{more}"


def _found(text: str, line: int, column: int) -> str:
    lines = text.splitlines()
    if not 1 <= line <= len(lines):
        return "end of file"
    rest = lines[line - 1][max(column - 1, 0) :].strip()
    if not rest:
        return "end of line"
    token = re.match(r"[A-Za-z_0-9]+|'[^']*'?|\S", rest)
    return f"'{token.group(0) if token else rest[:1]}'"


def location(obj: Any) -> tuple[int, int]:
    """Return the 1-based (line, column) where a parsed element starts."""
    where = get_location(obj)
    return int(where.get("line") or 0), int(where.get("col") or 0)


# ---------------------------------------------------------------- names and values


def unquote_name(raw: str) -> str:
    """Return the name a basic or quoted (``'x y'``) name denotes."""
    if len(raw) >= 2 and raw[0] == "'" and raw[-1] == "'":
        return _unescape(raw[1:-1])
    return raw


def name_segments(raw: str) -> tuple[str, ...]:
    """Split a qualified name ``A::'b c'::D`` into its unquoted segments."""
    return tuple(unquote_name(segment) for segment in _SEGMENT.findall(raw))


def simple_name(raw: str) -> str:
    """The last segment of a qualified name, unquoted."""
    segments = name_segments(raw)
    return segments[-1] if segments else raw


def identification(element: Any) -> tuple[str | None, str | None]:
    """Return ``(short_name, name)`` of an element declared with ``<short> name``."""
    ident = getattr(element, "ident", None)
    if ident is None:
        declaration = getattr(element, "declaration", None)
        ident = getattr(declaration, "ident", None)
    if ident is None:
        return None, None
    short = unquote_name(ident.shortName) if ident.shortName else None
    name = unquote_name(ident.name) if ident.name else None
    return short, name


def _unescape(text: str) -> str:
    return _ESCAPE.sub(lambda m: _ESCAPES.get(m.group(1), m.group(1)), text)


def doc_text(body: str) -> str:
    """The text of a ``/* ... */`` comment body: markers and leading ``*`` removed, the
    lines joined by single spaces."""
    text = body
    if text.startswith("/*"):
        text = text[2:]
    if text.endswith("*/"):
        text = text[:-2]
    lines = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("*"):
            line = line[1:].strip()
        if line:
            lines.append(line)
    return " ".join(lines)


def multiplicity(declaration: Any) -> tuple[int, int | None] | None:
    """``(lower, upper)`` of a usage declaration's multiplicity, ``upper`` None for ``*``;
    None when the declaration gives no range. ``[n]`` is n..n, ``[*]`` is 0..*.

    Raises ValueError for a bound that is a name rather than a number.
    """
    part = getattr(declaration, "multiplicity", None)
    if part is None or part.range is None:
        return None
    lower_raw, upper_raw = part.range.lower, part.range.upper
    if not upper_raw:
        if lower_raw == "*":
            return 0, None
        bound = _bound(lower_raw)
        return bound, bound
    lower = 0 if lower_raw == "*" else _bound(lower_raw)
    upper = None if upper_raw == "*" else _bound(upper_raw)
    return lower, upper


def _bound(raw: str) -> int:
    if raw.isdigit():
        return int(raw)
    raise ValueError(f"multiplicity bound '{raw}' is not a number")


def literal_value(expression: Any) -> object:
    """The Python value of a literal expression: int, float, str, bool or None.

    A feature reference gives its qualified name as a string (e.g. ``AgentType::C``);
    ``-``/``+`` apply to numbers.
    """
    expression = unwrap(expression)
    kind = rule(expression)
    if kind == "LiteralInteger":
        return int(expression.value)
    if kind == "LiteralReal":
        return float(expression.value)
    if kind == "LiteralString":
        return _unescape(expression.value[1:-1])
    if kind == "LiteralBoolean":
        return expression.value == "true"
    if kind == "LiteralNull":
        return None
    if kind == "FeatureReference" and not expression.chain and expression.index is None:
        return "::".join(name_segments(expression.name))
    if kind == "UnaryExpression":
        operand = literal_value(expression.operand)
        if expression.operator == "-" and isinstance(operand, (int, float)):
            return -operand
        if expression.operator == "+" and isinstance(operand, (int, float)):
            return operand
        if expression.operator == "not" and isinstance(operand, bool):
            return not operand
    raise ValueError(f"not a literal value: {rule(expression)}")


def unwrap(expression: Any) -> Any:
    """The expression a single-operand level stands for: ``or``/``and`` chains of one operand,
    comparisons without a right side and parentheses are left out."""
    while True:
        kind = rule(expression)
        if kind in ("OrExpression", "AndExpression") and not expression.rest:
            expression = expression.first
        elif kind == "ComparisonExpression" and expression.right is None:
            expression = expression.left
        elif kind == "ParenthesizedExpression":
            expression = expression.inner
        else:
            return expression


# ---------------------------------------------------------------- walking


def rule(obj: Any) -> str:
    """The grammar rule an object was parsed by (its textX class name)."""
    return type(obj).__name__


def members(element: Any) -> Iterator[Any]:
    """The elements owned by a namespace, a definition or a usage, in text order."""
    if rule(element) == "RootNamespace":
        yield from element.members
        return
    body = getattr(element, "body", None)
    if body is not None and hasattr(body, "members"):
        yield from body.members

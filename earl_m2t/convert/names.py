"""Names and conditions as SysML v2 text: quoting, and predicates as SysML v2 expressions."""

from __future__ import annotations

import re
from functools import cache

from earl_m2t.sysml2.conditions import FUNCTION, NotACondition, predicate_text
from earl_m2t.sysml2.parser import Sysml2SyntaxError, members, parse_text, rule, unwrap
from earl_m2t.sysml2.subset import subset

_BASIC = re.compile(r"[A-Za-z_][A-Za-z_0-9]*\Z")
_TOKEN = re.compile(
    r"\s+|∧|∨|¬|&&|\|\||==|!=|<=|>=|[<>!(),]|\[[0-9]+\]|[0-9]+(?:\.[0-9]+)?"
    r"|[A-Za-z_][A-Za-z_0-9]*(?:/[A-Za-z_][A-Za-z_0-9]*)?|."
)
_WORDS = {"∧": "and", "&&": "and", "and": "and", "∨": "or", "||": "or", "or": "or",
          "¬": "not ", "!": "not ", "not": "not ", "TRUE": "true", "FALSE": "false"}


def quoted(name: str) -> str:
    """A name as SysML v2 writes it: basic when it can be, else ``'quoted'``."""
    if _BASIC.match(name) and name not in subset().keywords:
        return name
    return "'" + name.replace("\\", "\\\\").replace("'", "\\'") + "'"


def qualified(name: str) -> str:
    return "::".join(quoted(part) for part in name.split("::"))


# Suffixes of names that a SysML v2 expression cannot refer to: the accesses of a function to
# the internal memory (`x/mi`, `x/mo`) are not features of the subsystem, and a primitive
# predicate (`x/pp`) is a calculation definition, invoked as `'x/pp'()` for `x/pp.fun`.
_NOT_FEATURES = frozenset({"mi", "mo", "pp"})


def expression(text: str) -> str | None:
    """The SysML v2 expression that reads back as exactly this predicate text, or None when
    there is none or it would refer to what is not a feature of the subsystem."""
    parts: list[str] = []
    tokens = [token for token in _TOKEN.findall(text) if not token.isspace()]
    for i, token in enumerate(tokens):
        if i >= 2 and tokens[i - 1] == "." and tokens[i - 2].endswith("/pp") and token == FUNCTION:
            parts[-1] = "()"  # `x/pp.fun` → `'x/pp'()`
        elif "/" in token and token.rpartition("/")[2] in _NOT_FEATURES and not (
                token.endswith("/pp") and tokens[i + 1:i + 3] == [".", FUNCTION]):
            return None
        elif token in _WORDS:
            word = _WORDS[token]
            parts.append(f" {word} " if word in ("and", "or") else word)
        elif token in ("==", "!=", "<=", ">=", "<", ">"):
            parts.append(f" {token} ")
        elif token == ",":
            parts.append(", ")
        elif token[0].isalpha() or token[0] == "_":
            parts.append(quoted(token) if "/" in token or token in subset().keywords else token)
        elif token[0] == "[" and len(token) > 2:
            parts.append(f"#({int(token[1:-1]) + 1})")  # `q[5]` → `q#(6)`: SysML v2 counts from 1
        elif token == "." or token in "()" or token[0].isdigit():
            parts.append(token)
        else:
            return None
    candidate = "".join(parts).strip()
    return candidate if candidate and reads_as(candidate) == text else None


@cache
def reads_as(candidate: str) -> str | None:
    """The predicate text the reader makes of an expression, None when it is none."""
    try:
        root = parse_text(f"constraint c {{ {candidate} }}", model=True)
    except Sysml2SyntaxError:
        return None
    (constraint,) = list(members(root))
    results = [m for m in members(constraint) if rule(m) == "ResultExpression"]
    if len(results) != 1 or len(list(members(constraint))) != 1:
        return None
    try:
        return predicate_text(unwrap(results[0].expression))
    except NotACondition:
        return None

"""Parsing OCL invariants and expressions (grammar ``metamodel/grammar/ocl.tx``).

The textX model is turned into the frozen syntax tree of :mod:`earl_m2t.ocl.ast` right away
and compiled; no textX object or exception leaves this module.
"""

from __future__ import annotations

import re
from functools import cache
from typing import Any

from textx import metamodel_from_file
from textx.exceptions import TextXError, TextXSyntaxError
from textx.metamodel import TextXMetaModel

import earl_m2t.ocl.ast as ast
from earl_m2t.ocl.errors import OclSyntaxError
from earl_m2t.ocl.evaluator import CompiledExpression, compile_expression
from earl_m2t.ocl.invariant import Invariant
from earl_m2t.ocl.limits import oversized
from earl_m2t.resources import metamodel_path

# Marks a single expression for the grammar's root rule; followed by a newline, so line
# numbers shift by exactly one and columns not at all.
_EXPRESSION_MARKER = "__expression__\n"
# what a text the pre-scan lets through but the parser cannot descend (if … endif, let … in chains)
_TOO_DEEP = "nested too deeply to parse ('if … endif' or 'let … in' inside one another): not read"


@cache
def _metamodel() -> TextXMetaModel:
    return metamodel_from_file(str(metamodel_path("grammar", "ocl.tx")), autokwd=True)


def parse_invariants(text: str, file: str = "<string>") -> list[Invariant]:
    """Parse a file of invariants; raises :class:`OclSyntaxError` on the first problem."""
    _refuse_oversized(text, file)
    try:
        return _invariants(text, file)
    except RecursionError:
        raise OclSyntaxError(_TOO_DEEP, file, 1, 1) from None


def _invariants(text: str, file: str) -> list[Invariant]:
    document = _parse(text, file, line_offset=0)
    if isinstance(document, str):  # textX gives '' for a file without any invariant
        return []
    if document.expression is not None:  # the marker reserved for parse_expression
        raise OclSyntaxError("expected 'context'", file, *_line_column(text, document._tx_position))
    builder = _Builder(text, file, position_offset=0)
    result: list[Invariant] = []
    seen: set[tuple[str, str]] = set()
    for invariant in document.invariants:
        line, column = _line_column(text, invariant._tx_position)
        key = (invariant.context, invariant.name)
        if key in seen:
            raise OclSyntaxError(
                f"duplicate invariant '{invariant.name}' for context {invariant.context}",
                file,
                line,
                column,
            )
        seen.add(key)
        expression = invariant.expression
        result.append(
            Invariant(
                context=invariant.context,
                name=invariant.name,
                expression=compile_expression(builder.build(expression)),
                source=text[expression._tx_position : expression._tx_position_end].strip(),
                line=line,
                column=column,
            )
        )
    return result


def parse_expression(text: str) -> CompiledExpression:
    """Parse a single expression; raises :class:`OclSyntaxError` (file ``<expression>``)."""
    file = "<expression>"
    _refuse_oversized(text, file)
    try:
        document = _parse(_EXPRESSION_MARKER + text, file, line_offset=1)
        if isinstance(document, str) or document.expression is None:  # cannot happen: the marker
            raise OclSyntaxError("expected an expression", file, 1, 1)  # starts an expression
        builder = _Builder(text, file, position_offset=len(_EXPRESSION_MARKER))
        return compile_expression(builder.build(document.expression))
    except RecursionError:
        raise OclSyntaxError(_TOO_DEEP, file, 1, 1) from None


# ---------------------------------------------------------------------------- textX → AST


class _Builder:
    """Turns textX expression objects into :mod:`earl_m2t.ocl.ast` nodes, checking names."""

    def __init__(self, text: str, file: str, position_offset: int) -> None:
        self.text = text
        self.file = file
        self.offset = position_offset

    def error(self, message: str, obj: Any) -> OclSyntaxError:
        line, column = _line_column(self.text, obj._tx_position - self.offset)
        return OclSyntaxError(message, self.file, line, column)

    def build(self, obj: Any) -> ast.Node:
        kind = obj.__class__.__name__
        method = getattr(self, f"_build_{kind}")
        return method(obj)

    def _fold(self, obj: Any) -> ast.Node:
        node = self.build(obj.operands[0])
        for operator, operand in zip(obj.operators, obj.operands[1:]):
            node = ast.Binary(operator, node, self.build(operand))
        return node

    _build_ImpliesExpr = _fold
    _build_LogicExpr = _fold
    _build_CompareExpr = _fold
    _build_AdditiveExpr = _fold
    _build_MultiplicativeExpr = _fold

    def _build_NotExpr(self, obj: Any) -> ast.Node:
        return ast.Unary("not", self.build(obj.operand))

    def _build_NegateExpr(self, obj: Any) -> ast.Node:
        operand = self.build(obj.operand)
        if isinstance(operand, ast.Literal) and type(operand.value) in (int, float):
            return ast.Literal(-operand.value)  # type: ignore[operator]
        return ast.Unary("-", operand)

    def _build_PostfixExpr(self, obj: Any) -> ast.Node:
        node = self.build(obj.base)
        for suffix in obj.suffixes:
            node = self._suffix(node, suffix)
        return node

    def _suffix(self, source: ast.Node, suffix: Any) -> ast.Node:
        kind = suffix.__class__.__name__
        name = suffix.name
        if kind == "DotNavigation":
            if name.startswith("__"):
                raise self.error(f"'{name}' is not a navigable attribute", suffix)
            return ast.Navigation(source, name)
        if kind == "IteratorCall":
            if name not in ast.ITERATORS:
                raise self.error(
                    f"unknown iterator '{name}'; expected one of {_listing(ast.ITERATORS)}", suffix
                )
            return ast.Iterate(source, name, suffix.variable, self.build(suffix.body))
        arguments = tuple(self.build(argument) for argument in suffix.arguments)
        if kind == "ArrowCall":
            if name in ast.ITERATORS:
                raise self.error(f"iterator '{name}' needs a variable: ->{name}(v | ...)", suffix)
            table, call = ast.COLLECTION_ARITY, "->"
        else:
            table, call = ast.METHOD_ARITY, "."
        if name not in table:
            hint = ""
            other = ast.METHOD_ARITY if call == "->" else ast.COLLECTION_ARITY
            if name in other or name in ast.ITERATORS:
                hint = f" (did you mean '{'.' if call == '->' else '->'}{name}'?)"
            raise self.error(f"unknown operation '{call}{name}()'{hint}", suffix)
        expected = table[name]
        if len(arguments) != expected:
            plural = "" if expected == 1 else "s"
            raise self.error(
                f"'{call}{name}()' takes {expected} argument{plural}, got {len(arguments)}", suffix
            )
        if call == "->":
            return ast.CollectionCall(source, name, arguments)
        return ast.MethodCall(source, name, arguments)

    def _build_IfExpr(self, obj: Any) -> ast.Node:
        return ast.If(
            self.build(obj.condition), self.build(obj.then_branch), self.build(obj.else_branch)
        )

    def _build_LetExpr(self, obj: Any) -> ast.Node:
        return ast.Let(obj.variable, self.build(obj.value), self.build(obj.body))

    def _build_ParenExpr(self, obj: Any) -> ast.Node:
        return self.build(obj.inner)

    def _build_SelfExpr(self, obj: Any) -> ast.Node:
        return ast.Variable("self")

    def _build_VariableExpr(self, obj: Any) -> ast.Node:
        return ast.Variable(obj.name)

    def _build_RealLiteral(self, obj: Any) -> ast.Node:
        return ast.Literal(float(obj.value))

    def _build_IntegerLiteral(self, obj: Any) -> ast.Node:
        return ast.Literal(int(obj.value))

    def _build_StringLiteral(self, obj: Any) -> ast.Node:
        return ast.Literal(_unescape(obj.value[1:-1]))

    def _build_BooleanLiteral(self, obj: Any) -> ast.Node:
        return ast.Literal(obj.value == "true")

    def _build_NullLiteral(self, obj: Any) -> ast.Node:
        return ast.Literal(None)


_ESCAPES = {"n": "\n", "t": "\t", "r": "\r"}


def _unescape(body: str) -> str:
    return re.sub(r"\\(.)", lambda m: _ESCAPES.get(m.group(1), m.group(1)), body)


def _listing(names: Any) -> str:
    return ", ".join(sorted(names))


# ---------------------------------------------------------------------------- errors


def _parse(text: str, file: str, line_offset: int) -> Any:
    try:
        return _metamodel().model_from_str(text)
    except TextXSyntaxError as error:
        # the parser may report the position before the whitespace that precedes the token
        position = _skip_ws(text, _position(text, error.line or 1, error.col or 1))
        message = _describe(text, position, error.expected_rules or [])
        line, column = _line_column(text, position)
        raise OclSyntaxError(message, file, line - line_offset, column) from None
    except TextXError as error:  # not expected from this grammar; still one readable line
        message = str(getattr(error, "message", error)).splitlines()[0]
        line = (error.line or 1) - line_offset
        raise OclSyntaxError(message, file, line, error.col or 1) from None


# What a parse failure expected, in words. Regular expressions of the grammar map to a
# description; keywords and punctuation are shown quoted.
_DESCRIPTIONS = {
    r"[A-Za-z_][A-Za-z0-9_]*": "a name",
    r"[A-Za-z0-9_]+([.-][A-Za-z0-9_]+)*": "an invariant name",
    r"[A-Za-z_][A-Za-z0-9_]*(::[A-Za-z_][A-Za-z0-9_]*)*": "a type name",
    r"[0-9]+(\.[0-9]+([eE][+-]?[0-9]+)?|[eE][+-]?[0-9]+)": "a number",
    r"[0-9]+": "a number",
    r"'(\\.|[^'\\\n])*'": "a string",
    r"-(?!>)": "'-'",
}
_HIDDEN = {r"--[^\n]*", "__expression__"}
_EXPRESSION_START = {"not", "if", "let", "(", "self", "true", "false", "null"}
_OPERANDS = _EXPRESSION_START | {"a name", "a number", "a string", "'-'"}
_OPERATORS = {"*", "/", "+", "'-'", "<>", "<=", ">=", "=", "<", ">", "and", "or", "xor", "implies"}


def _describe(text: str, position: int, expected_rules: list[Any]) -> str:
    words: list[str] = []
    for rule in expected_rules:
        pattern = getattr(rule, "to_match", None)
        if type(rule).__name__ == "Not":  # the grammar's only negative lookahead: Name
            word = "a name"
        elif pattern is None:
            word = "end of input"
        elif pattern in _HIDDEN:
            continue
        else:
            word = _DESCRIPTIONS.get(pattern, pattern)
        if word not in words:
            words.append(word)
    if set(words) >= _EXPRESSION_START:
        words = [w for w in words if w not in _OPERANDS]
        words.insert(0, "an expression")
    if set(words) >= _OPERATORS:
        words = [w for w in words if w not in _OPERATORS]
        words.insert(0, "an operator")
    words = [w if w.startswith(("a ", "an ", "end ", "'")) else f"'{w}'" for w in words]
    expected = " or ".join(words) if len(words) <= 2 else ", ".join(words[:-1]) + " or " + words[-1]
    found = _found(text, position)
    if found.startswith("unterminated"):
        return found
    return f"unexpected {found}; expected {expected}"


_TOKEN = re.compile(
    r"'(?:\\.|[^'\\\n])*'?|[A-Za-z_][A-Za-z0-9_]*|[0-9]+(?:\.[0-9]+)?|->|<>|<=|>=|\S"
)


def _found(text: str, position: int) -> str:
    match = _TOKEN.match(text, _skip_ws(text, position))
    if match is None:
        return "end of input"
    token = match.group(0)
    if len(token) > 30:
        token = token[:27] + "..."
    if not token.startswith("'"):
        return repr(token)
    if len(token) == 1 or not token.endswith("'"):
        return f"unterminated string {token}"
    return f"string {token}"


def _skip_ws(text: str, position: int) -> int:
    """The position of the next token: whitespace and ``--`` comments skipped."""
    while position < len(text):
        if text[position].isspace():
            position += 1
        elif text.startswith("--", position):
            newline = text.find("\n", position)
            position = len(text) if newline < 0 else newline
        else:
            break
    return position


def _position(text: str, line: int, column: int) -> int:
    offset = 0
    for _ in range(line - 1):
        newline = text.find("\n", offset)
        if newline < 0:
            return len(text)
        offset = newline + 1
    return offset + column - 1


def _refuse_oversized(text: str, file: str) -> None:
    found = oversized(text)
    if found is not None:
        raise OclSyntaxError(found[1], file, *_line_column(text, found[0]))


def _line_column(text: str, position: int) -> tuple[int, int]:
    line = text.count("\n", 0, position) + 1
    column = position - (text.rfind("\n", 0, position) + 1) + 1
    return line, column

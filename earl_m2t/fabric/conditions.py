"""FABRIC's condition text (``recvStatus and (not rLwrOk or TRUE)``) as an EARL predicate.

The grammar ``logicExprToCpp`` accepts: predicate names, ``TRUE``, ``FALSE``, ``and``, ``or``,
``not``, parentheses; C++'s precedence applies to what it makes (not, then and, then or).
FABRIC's run-time flags ``IN_ERROR`` and ``CURRENT_BEHAVIOR_OK`` are EARL's built-ins
``inError()`` and ``behaviourOk()``.

A package is untrusted input: a condition of more than ``MAX_OPERATORS`` operators, or nested
(parentheses and ``not``) more than ``MAX_NESTING`` levels deep, is refused before it is parsed,
as the SysML v2 reader refuses the text the importer would write of it.
"""

from __future__ import annotations

import re

from earl_m2t.model.limits import MAX_NESTING, MAX_OPERATORS
from earl_m2t.predicate import And, BuiltIn, BuiltInPredicate, Const, Expr, Not, Or, PredicateRef

TOKEN = re.compile(r"\s*(?:(\()|(\))|([A-Za-z_][A-Za-z0-9_]*))")
# FABRIC's run-time flags (create_master_cpp.py adds them to every predicate list)
FLAGS = {"IN_ERROR": BuiltInPredicate.IN_ERROR, "CURRENT_BEHAVIOR_OK": BuiltInPredicate.BEHAVIOUR_OK}
OPERATORS = frozenset(("and", "or", "not"))


class ConditionError(Exception):
    """A condition FABRIC would not translate, or that names no predicate of the package."""


def parse_fabric_condition(text: str, predicates: dict[str, str]) -> Expr:
    """The condition over EARL predicate names; ``predicates`` maps FABRIC names to them."""
    tokens = _tokens(text)
    if not tokens:
        raise ConditionError("an empty condition (FABRIC writes TRUE or FALSE)")
    _check_size(tokens)
    parser = _Parser(tokens, predicates)
    expr = parser.disjunction()
    if parser.position != len(tokens):
        raise ConditionError(f"unexpected '{tokens[parser.position]}'")
    return expr


def _tokens(text: str) -> list[str]:
    tokens: list[str] = []
    position = 0
    text = text.rstrip()
    while position < len(text):
        found = TOKEN.match(text, position)
        if found is None:
            raise ConditionError(f"unexpected character '{text[position:].lstrip()[:1]}'")
        tokens.append(found.group(found.lastindex or 0))
        position = found.end()
    return tokens


def _check_size(tokens: list[str]) -> None:
    """Refuse a condition with more operators than a condition may have."""
    operators = sum(token in OPERATORS for token in tokens)
    if operators > MAX_OPERATORS:
        raise ConditionError(f"{operators:,} operators, more than the {MAX_OPERATORS:,} a condition may have")


class _Parser:
    def __init__(self, tokens: list[str], predicates: dict[str, str]) -> None:
        self.tokens = tokens
        self.position = 0
        self.predicates = predicates
        self.depth = 0  # parentheses and 'not's the descent is inside: each is a frame

    def deeper(self) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise ConditionError(f"nested more than {MAX_NESTING} levels deep (parentheses and 'not')")

    def peek(self) -> str:
        return self.tokens[self.position] if self.position < len(self.tokens) else ""

    def take(self) -> str:
        token = self.peek()
        if not token:
            raise ConditionError("the condition ends too early")
        self.position += 1
        return token

    def disjunction(self) -> Expr:
        operands = [self.conjunction()]
        while self.peek() == "or":
            self.take()
            operands.append(self.conjunction())
        return operands[0] if len(operands) == 1 else Or(tuple(operands))

    def conjunction(self) -> Expr:
        operands = [self.negation()]
        while self.peek() == "and":
            self.take()
            operands.append(self.negation())
        return operands[0] if len(operands) == 1 else And(tuple(operands))

    def negation(self) -> Expr:
        if self.peek() == "not":
            self.take()
            self.deeper()
            operand = self.negation()
            self.depth -= 1
            return Not(operand)
        return self.atom()

    def atom(self) -> Expr:
        token = self.take()
        if token == "(":
            self.deeper()
            expr = self.disjunction()
            if self.take() != ")":
                raise ConditionError("a '(' is not closed")
            self.depth -= 1
            return expr
        if token in ("TRUE", "FALSE"):
            return Const(token == "TRUE")
        if token in FLAGS:
            return BuiltIn(FLAGS[token])
        if token in self.predicates:
            return PredicateRef(self.predicates[token])
        raise ConditionError(f"'{token}' is not a <predicate> of the subsystem")

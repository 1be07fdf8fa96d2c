"""A small OCL-like constraint language: invariants over Python objects.

    context Agent inv S003: self.cs->size() = 1

:func:`parse_invariants` reads a file of invariants, :func:`parse_expression` a single
expression; :func:`evaluate` computes an expression with ``self`` bound to an object and
:func:`check` evaluates an invariant that must yield a Boolean. Matching an invariant's
``context`` type name to objects is left to the caller.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from earl_m2t.ocl.errors import OclEvaluationError, OclSyntaxError
from earl_m2t.ocl.evaluator import CompiledExpression, evaluate
from earl_m2t.ocl.invariant import Invariant

if TYPE_CHECKING:
    from earl_m2t.ocl.parser import parse_expression, parse_invariants

_PARSER_NAMES = ("parse_expression", "parse_invariants")


def __getattr__(name: str) -> Any:
    """The parsers on first use: the grammar (textX) is loaded only when text is parsed."""
    if name not in _PARSER_NAMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from earl_m2t.ocl import parser

    value = getattr(parser, name)
    globals()[name] = value
    return value


def check(invariant: Invariant, obj: object) -> bool:
    """Evaluate ``invariant`` on ``obj``; a result that is not a Boolean is an error."""
    result = evaluate(invariant.expression, obj)
    if result is True or result is False:
        return result
    raise OclEvaluationError(
        f"invariant {invariant.name} must give a Boolean, got {type(result).__name__} ({result!r})"
    )


__all__ = [
    "CompiledExpression",
    "Invariant",
    "OclEvaluationError",
    "OclSyntaxError",
    "check",
    "evaluate",
    "parse_expression",
    "parse_invariants",
]

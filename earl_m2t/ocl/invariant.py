"""A parsed invariant, apart from the parser: the cached invariants are read back without
loading the grammar (textX)."""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.ocl.evaluator import CompiledExpression


@dataclass(frozen=True)
class Invariant:
    """``context <context> inv <name>: <expression>``, with where it starts in its file."""

    context: str
    name: str
    expression: CompiledExpression
    source: str
    line: int
    column: int

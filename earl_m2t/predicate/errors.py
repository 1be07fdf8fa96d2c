"""The one exception of the predicate language."""

from __future__ import annotations


def where(line: int, column: int) -> str:
    """``column 5``, or ``line 2, column 5`` past the first line."""
    return f"line {line}, column {column}" if line > 1 else f"column {column}"


class PredicateSyntaxError(Exception):
    """A predicate text that does not parse, with the 1-based line and column of the fault."""

    def __init__(self, message: str, line: int, column: int) -> None:
        super().__init__(message, line, column)
        self.message = message
        self.line = line
        self.column = column

    def __str__(self) -> str:
        return self.message

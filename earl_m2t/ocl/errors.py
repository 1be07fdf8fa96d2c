"""The two errors of the OCL package: one for text that does not parse, one for evaluation."""

from __future__ import annotations

from earl_m2t.diagnostics import SourceTextError


class OclSyntaxError(SourceTextError):
    """Constraint text that does not parse, with the 1-based line and column of the problem."""

    def __init__(self, message: str, file: str, line: int, column: int) -> None:
        super().__init__(file, line, column, message)


class OclEvaluationError(Exception):
    """An expression that cannot be evaluated on the given objects.

    Type errors, missing attributes, unknown variables, invalid regular expressions.
    """

    def __init__(self, message: str) -> None:
        self.message = message
        super().__init__(message)

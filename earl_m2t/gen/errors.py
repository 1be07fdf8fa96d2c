"""The error of code generation."""


class GenError(Exception):
    """The model cannot be generated for a target (one line, shown as is)."""

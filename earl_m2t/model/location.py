"""Source locations carried by every element read from a model file."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Location:
    """Where an element comes from: file, 1-based line (0 when unknown), column, XMI id."""

    file: str
    line: int = 0
    column: int = 0
    xmi_id: str = ""

    def __str__(self) -> str:
        if self.line and self.column:
            return f"{self.file}:{self.line}:{self.column}"
        if self.line:
            return f"{self.file}:{self.line}"
        return self.file


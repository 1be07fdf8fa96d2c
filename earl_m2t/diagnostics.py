"""The single diagnostic type produced by every stage (read, lift, check)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from earl_m2t.model.location import Location
from earl_m2t.shorten import shortened_words


class Severity(StrEnum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"

    @property
    def rank(self) -> int:
        return {"error": 0, "warning": 1, "info": 2}[self.value]

    @classmethod
    def parse(cls, text: str) -> Severity:
        key = text.strip().lower()
        aliases = {"e": "error", "w": "warning", "i": "info"}
        return cls(aliases.get(key, key))


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One finding: a stable rule code, a severity, a message, and where it is."""

    code: str
    severity: Severity
    message: str
    location: Location
    element: str = ""  # the element path, e.g. ``manip/a.cs.fsm.idle,jointMove/t``

    def sort_key(self) -> tuple[str, int, int, str, str, str]:
        loc = self.location
        return (loc.file, loc.line, loc.column, self.code, self.element, self.message)


class SourceTextError(Exception):
    """Text in one of earl-m2t's languages (profile, rules) that does not parse or is inconsistent.

    ``str()`` is ``file:line:col: message``; line and column are 1-based (0 when unknown).
    """

    def __init__(self, file: str, line: int, column: int, message: str) -> None:
        self.file = file
        self.line = line
        self.column = column
        self.message = message
        super().__init__(f"{file}:{line}:{column}: {message}")


class ModelReadError(Exception):
    """A model file that cannot be read at all: reported as one line, exit code 2."""

    def __init__(self, file: str, message: str, line: int = 0, element: str = "") -> None:
        self.file = file
        self.line = line
        self.element = element
        self.message = message
        super().__init__(self.one_line())

    def one_line(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        what = f" [{self.element}]" if self.element else ""
        return shortened_words(f"{where}: error: {self.message}{what}")

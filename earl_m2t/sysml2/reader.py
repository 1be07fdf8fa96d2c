"""Read a SysML v2 textual model (``.sysml``) into the raw model the XMI lift reads.

The text is parsed with the model grammar (``metamodel/grammar/sysml2-model.tx``), said in
UML by :mod:`earl_m2t.sysml2.to_xmi`, and indexed like an XMI file. Constructs outside the
subset are R007 findings with line and column; text that does not parse is one
``file:line:col: error: ...`` line (:class:`Sysml2ReadError`).
"""

from __future__ import annotations

from pathlib import Path

from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity
from earl_m2t.model.location import Location
from earl_m2t.profile import load_profile
from earl_m2t.read.xmi import RawModel
from earl_m2t.read.xmi_index import index_tree
from earl_m2t.shorten import shortened_words
from earl_m2t.sysml2.parser import Sysml2SyntaxError, parse_file
from earl_m2t.sysml2.subset import Outside, outside_constructs
from earl_m2t.sysml2.to_xmi import build_xmi

DIALECT = "sysml-v2"
OUTSIDE_CODE = "R007"


class Sysml2ReadError(ModelReadError):
    """A SysML v2 file that cannot be read: ``file:line:col: error: message``."""

    def __init__(self, file: str, message: str, line: int = 0, column: int = 0) -> None:
        self.column = column
        super().__init__(file, message, line)

    def one_line(self) -> str:
        if self.line and self.column:
            return shortened_words(f"{self.file}:{self.line}:{self.column}: error: {self.message}")
        return super().one_line()


def read_sysml2(path: Path) -> RawModel:
    """The raw model of a ``.sysml`` file; raises :class:`Sysml2ReadError` when unreadable."""
    file = str(path)
    try:
        root = parse_file(path, model=True)
    except Sysml2SyntaxError as error:
        raise Sysml2ReadError(file, error.message, error.line, error.column) from None
    built = build_xmi(root, file, load_profile())
    raw = index_tree(built.model, file, "papyrus")
    raw.dialect = DIALECT
    raw.stereotypes = built.stereotypes
    raw.diagnostics.extend(outside_finding(file, o) for o in outside_constructs(root))
    return raw


def outside_finding(file: str, outside: Outside) -> Diagnostic:
    what = (f"this '{outside.construct}' is not in a form the EARL SysML v2 subset reads (docs/sysml-v2.md)"
            if outside.malformed else f"construct '{outside.construct}' is outside the EARL SysML v2 subset")
    return Diagnostic(
        OUTSIDE_CODE,
        Severity.WARNING,
        f"{what} (column {outside.column})",
        Location(file, outside.line, outside.column),
        outside.construct,
    )

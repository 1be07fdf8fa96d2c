"""What one ``check`` run found, as every output format of :mod:`earl_m2t.render.diagnostics` renders it."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from earl_m2t.diagnostics import Diagnostic


@dataclass(frozen=True)
class CheckReport:
    """Everything one ``check`` run found, as every output format needs it."""

    diagnostics: list[Diagnostic]
    checked: list[str]  # files read and checked
    unreadable: list[dict[str, object]] = field(default_factory=list)  # file, line, message
    rules: Sequence[str] | None = None  # codes of the rules that ran (None: the whole catalogue)

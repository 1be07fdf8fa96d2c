"""Which files are SysML v2 text: the one place that knows the suffix."""

from __future__ import annotations

from pathlib import Path

SUFFIX = ".sysml"


def is_sysml2(path: Path) -> bool:
    return path.suffix.lower() == SUFFIX

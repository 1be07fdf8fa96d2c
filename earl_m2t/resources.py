"""The one place that knows where the data folders (metamodel, profiles, transforms) are.

An installed wheel carries them as ``earl_m2t/_data/<folder>``; an editable install or a
checkout uses the top-level folders beside the package, so edits take effect at once.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

_PACKAGE_DIR = Path(__file__).resolve().parent


@cache
def data_dir(folder: str) -> Path:
    """Return the directory of a data folder: ``metamodel``, ``profiles`` or ``transforms``."""
    for candidate in (_PACKAGE_DIR / "_data" / folder, _PACKAGE_DIR.parent / folder):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"earl-m2t data folder '{folder}' is missing from the installation")


def metamodel_path(*parts: str) -> Path:
    return data_dir("metamodel").joinpath(*parts)


def profile_path(name: str = "earl.sysml") -> Path:
    return data_dir("profiles") / name

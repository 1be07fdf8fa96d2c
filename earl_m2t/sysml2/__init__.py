"""SysML v2 textual notation: parsing with the grammar ``metamodel/grammar/sysml2.tx``.

The names below come from :mod:`earl_m2t.sysml2.parser` on first use (PEP 562), so that
:mod:`earl_m2t.sysml2.files` (is this file SysML v2 text?) does not load textX.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from earl_m2t.sysml2.parser import (
        Sysml2SyntaxError,
        doc_text,
        identification,
        literal_value,
        location,
        members,
        multiplicity,
        name_segments,
        parse_file,
        parse_text,
        rule,
        simple_name,
        unquote_name,
        unwrap,
    )

__all__ = [
    "Sysml2SyntaxError",
    "doc_text",
    "identification",
    "literal_value",
    "location",
    "members",
    "multiplicity",
    "name_segments",
    "parse_file",
    "parse_text",
    "rule",
    "simple_name",
    "unquote_name",
    "unwrap",
]


def __getattr__(name: str) -> Any:
    if name not in __all__:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module("earl_m2t.sysml2.parser"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))

"""Model names → valid, distinct C++ identifiers (and the file names made from them).

Rules D003/D004 reject names that are not identifiers or that collide; a forced generation
still needs valid, distinct names, so every name is mangled deterministically:
non-ASCII letters lose their accents (``ü`` → ``u``) or become ``uXXXX``, anything else
that is not ``[A-Za-z0-9_]`` becomes ``_``, runs of ``_`` collapse (``__`` is reserved in
C++), a leading digit gets an ``n`` prefix, keywords get a trailing ``_``; within one scope
a name already taken (compared case-insensitively, as file names are on some disks) gets
``_2``, ``_3`` … in model order.
"""

from __future__ import annotations

import re
import tomllib
from functools import cache

from earl_m2t.model.naming import ascii_fold, identifier
from earl_m2t.resources import metamodel_path

# names the generated code itself uses, or standard macros, in any scope
_ALWAYS_RESERVED = frozenset({
    "NULL", "EOF", "assert", "errno", "stdin", "stdout", "stderr", "main", "std", "earl",
    "offsetof", "setjmp", "va_arg", "BUFSIZ", "SIZE_MAX", "INT64_MAX",
})


@cache
def _keywords() -> frozenset[str]:
    table = tomllib.loads(metamodel_path("tables", "identifiers.toml").read_text(encoding="utf-8"))
    return frozenset(table["cpp_keywords"]) | {"final", "override", "import", "module"}


def is_reserved(name: str) -> bool:
    """A C++ keyword, or a name the generated code itself uses in every scope."""
    return name in _keywords() or name in _ALWAYS_RESERVED


def cpp_identifier(name: str) -> str:
    """The C++ identifier of an EARL name (``motionFinished/m`` → ``motionFinished_m``)."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", ascii_fold(identifier(name.strip())))
    text = re.sub(r"_+", "_", text).strip("_")
    if not text:
        text = "unnamed"
    if text[0].isdigit():
        text = "n" + text
    if is_reserved(text):
        text += "_"
    return text


class Scope:
    """Hands out distinct identifiers within one C++ scope (or one folder)."""

    def __init__(self, reserved: tuple[str, ...] = ()) -> None:
        self._taken: set[str] = {r.lower() for r in reserved}
        self._last_number: dict[str, int] = {}

    def take(self, name: str, *derived: str) -> str:
        """A free identifier for ``name``; ``derived`` suffixes (``_base``) are reserved with it."""
        base = cpp_identifier(name)
        candidate, n = base, self._last_number.get(base.lower(), 1)
        if n > 1:
            candidate = f"{base}_{n}"
        while any((candidate + suffix).lower() in self._taken for suffix in ("", *derived)):
            n += 1
            candidate = f"{base}_{n}"
        self._last_number[base.lower()] = n  # the next name with this base starts here: linear, not quadratic
        for suffix in ("", *derived):
            self._taken.add((candidate + suffix).lower())
        return candidate


def cpp_string(text: str) -> str:
    """A C++ string literal holding ``text`` (UTF-8, every non-printable-ASCII byte escaped)."""
    out = ['"']
    for byte in text.encode("utf-8"):
        char = chr(byte)
        if char in '"\\':
            out.append("\\" + char)
        elif 0x20 <= byte < 0x7F and char != "?":
            out.append(char)
        else:
            out.append(f"\\{byte:03o}")
    out.append('"')
    return "".join(out)


def cpp_comment(text: str) -> str:
    """Text safe inside a ``//`` comment: one line, no backslash (a line splice)."""
    return " ".join(text.split()).replace("\\", "/")

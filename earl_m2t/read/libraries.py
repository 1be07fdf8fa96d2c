"""What the resource part of an href names: a known library, a model file beside the referring
file, or something that is never opened. The libraries are data: ``metamodel/xmi/libraries.toml``.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from functools import cache
from urllib.parse import unquote

from earl_m2t.resources import metamodel_path

_SCHEME = re.compile(r"^([A-Za-z][A-Za-z0-9+.-]*):")


@dataclass(frozen=True, slots=True)
class Resource:
    """The resource part of an href (before ``#``), classified.

    ``kind`` is ``library`` (``library`` then says which kind of library, from libraries.toml),
    ``file`` (``path`` is the relative path to read, %-decoded) or ``closed`` (never opened;
    ``reason`` says why, for the diagnostic).
    """

    text: str
    kind: str
    library: str = ""
    path: str = ""
    reason: str = ""


@cache
def library_table() -> tuple[tuple[re.Pattern[str], str], ...]:
    """(pattern, library kind) for each row of ``[libraries]``, in file order."""
    data = tomllib.loads(metamodel_path("xmi", "libraries.toml").read_text(encoding="utf-8"))
    rows = []
    for key, kind in data["libraries"].items():
        pattern = "".join("[^/]*" if part == "*" else re.escape(part) for part in re.split(r"(\*)", _normal(key)))
        rows.append((re.compile(pattern), str(kind)))
    return tuple(rows)


def _normal(resource: str) -> str:
    text = unquote(resource.strip()).lower()
    return "http://" + text[len("https://"):] if text.startswith("https://") else text


def library_kind(resource: str) -> str:
    """The kind of library a resource is (``primitive-types``, ``profile`` …), "" when none."""
    text = _normal(resource)
    return next((kind for pattern, kind in library_table() if pattern.match(text)), "")


@cache
def classify(resource: str) -> Resource:
    """What an href's resource part names; see the header of ``libraries.toml``."""
    kind = library_kind(resource)
    if kind:
        return Resource(resource, "library", library=kind)
    scheme = _SCHEME.match(resource)
    if scheme is not None and len(scheme.group(1)) > 1:
        return Resource(resource, "closed", reason=_closed_reason(scheme.group(1).lower()))
    path = unquote(resource)
    if scheme is not None or path.startswith(("/", "\\")):  # C:/… or /…
        return Resource(resource, "closed", reason="an absolute path, which is never opened; "
                        "reference the file by a path relative to the model")
    return Resource(resource, "file", path=path)


def _closed_reason(scheme: str) -> str:
    if scheme == "pathmap":
        return ("a pathmap earl-m2t does not know (a file inside a tool plug-in); copy the file beside "
                "the model and reference it by a relative path")
    if scheme == "platform":
        return ("a file of an Eclipse workspace or plug-in, which is never opened; reference it by a "
                "path relative to the model")
    if scheme in ("http", "https", "ftp"):
        return "a URL, which is never fetched"
    if scheme == "file":
        return "a file: URI, which is never opened; reference the file by a path relative to the model"
    return f"a {scheme}: URI, which earl-m2t does not open"

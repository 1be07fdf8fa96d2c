"""From a generated file and line to the model element it comes from, through the source map
(``.earl-trace.json``) of the output folder the file is in."""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from earl_m2t.trace.sourcemap import TRACE_FILE


@dataclass(frozen=True)
class Origin:
    """Where a generated line comes from. ``element`` is "" for a file no element generates
    (the runtime, copied as it is)."""

    element: str
    kind: str
    xmi_id: str
    model_file: str  # relative to the current folder when below it, else absolute
    model_line: int
    user_file: bool

    def describe(self) -> str:
        if not self.element:
            return "no model element (a file copied as it is, e.g. the runtime)"
        ident = f" (xmi:id {self.xmi_id})" if self.xmi_id else ""
        user = " (user file: the lines are yours)" if self.user_file else ""
        return f"{self.kind} {self.element}{ident}{user}"

    @property
    def where(self) -> str:
        return f"{self.model_file}:{self.model_line}" if self.model_line else self.model_file


class TraceError(Exception):
    """A source map that cannot be read: one line."""


class SourceMaps:
    """The source maps of the folders looked up so far (each read once)."""

    def __init__(self) -> None:
        self._maps: dict[Path, dict[str, Any] | None] = {}

    def _map(self, folder: Path) -> dict[str, Any] | None:
        if folder not in self._maps:
            path = folder / TRACE_FILE
            document: dict[str, Any] | None = None
            if path.is_file():
                try:
                    document = json.loads(path.read_text(encoding="utf-8"))
                except (OSError, ValueError, RecursionError) as error:
                    raise TraceError(f"{path}: not a source map ({type(error).__name__})") from None
                if not isinstance(document, dict) or not isinstance(document.get("files"), dict):
                    raise TraceError(f"{path}: not a source map (no 'files')")
            self._maps[folder] = document
        return self._maps[folder]

    def origin(self, file: str | Path, line: int) -> Origin | None:
        """The origin of ``file:line``, or None when no source map above the file names it."""
        absolute = Path(os.path.abspath(file))
        for candidate in dict.fromkeys([absolute, absolute.resolve()]):
            for folder in candidate.parents:
                document = self._map(folder)
                if document is None:
                    continue
                relative = candidate.relative_to(folder).as_posix()
                entry = document["files"].get(relative)
                if entry is not None:
                    try:
                        return _origin(document, folder, entry, line)
                    except (TypeError, ValueError, AttributeError):  # a map edited or corrupted by hand
                        raise TraceError(f"{folder / TRACE_FILE}: not a source map (its entry for {relative} "
                                         "is malformed)") from None
        return None


def _origin(document: dict[str, Any], folder: Path, entry: dict[str, Any], line: int) -> Origin:
    element = entry.get("element") or ""
    for first, last, specific in entry.get("lines", []):
        if first <= line <= last:
            element = specific
            break
    info = document.get("elements", {}).get(element, {})
    model_file = ""
    if info.get("file"):
        model_file = _shown(folder / info["file"])
    return Origin(element, str(info.get("kind", "")), str(info.get("xmi_id", "")), model_file,
                  int(info.get("line", 0)), bool(entry.get("user")))


def _shown(path: Path) -> str:
    absolute = os.path.normpath(os.path.abspath(path))
    relative = os.path.relpath(absolute)
    return Path(absolute).as_posix() if relative.startswith("..") else Path(relative).as_posix()


# what GCC and Clang print: FILE:LINE[:COLUMN]: error|warning|note: …
COMPILER_LINE = re.compile(r"^(?P<file>[^\s:][^:]*):(?P<line>\d+):(?:\d+:)?\s*(?:fatal )?(?:error|warning|note)\b")

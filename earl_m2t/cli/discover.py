"""Which files ``earl-m2t check DIR_OR_FILE...`` checks.

A file named on the command line is always checked. A directory is searched recursively, in
sorted order, for ``*.uml``, ``*.xmi``, ``*.mdzip`` and ``*.xml`` files that are XMI (an
Enterprise Architect export; other XML is passed over quietly), and for SysML v2 text
(``*.sysml``). Profiles (``*.profile.uml``),
Papyrus' diagram files (``.notation``, ``.di``) and hidden folders (``.git``, ``.venv``) are
skipped.
"""

from __future__ import annotations

import os
from pathlib import Path

from earl_m2t.sysml2.files import SUFFIX as SYSML2_SUFFIX

MODEL_SUFFIXES = (".uml", ".xmi", ".mdzip", ".xml", SYSML2_SUFFIX)
_XMI_MARKS = (b"omg.org/spec/XMI", b"schema.omg.org/spec/XMI", b"xmi:version", b"xmi.version")


def is_model_file(path: Path) -> bool:
    name = path.name.lower()
    if not name.endswith(MODEL_SUFFIXES) or name.endswith(".profile.uml") or name.startswith("."):
        return False
    if name.endswith(".xml"):
        try:
            with path.open("rb") as handle:
                head = handle.read(4096)
        except OSError:
            return False
        return any(mark in head for mark in _XMI_MARKS)
    return True


def _walk(folder: Path) -> list[Path]:
    """The model files under ``folder``; each folder is searched once, however links lead to it
    (a link to a folder above ends instead of looping), and without recursion."""
    found: list[Path] = []
    seen: set[str] = set()
    pending = [folder]
    while pending:
        current = pending.pop()
        real = os.path.realpath(current)
        if real in seen:
            continue
        seen.add(real)
        try:
            entries = sorted(current.iterdir(), key=lambda p: p.name)
        except OSError:
            continue  # unreadable or vanished: nothing to check in it
        folders = []
        for entry in entries:
            if entry.name.startswith("."):
                continue
            if entry.is_dir():
                folders.append(entry)
            elif entry.is_file() and is_model_file(entry):
                found.append(entry)
        pending.extend(reversed(folders))
    return sorted(found, key=lambda p: p.parts)


def model_files(arguments: list[str]) -> tuple[list[str], list[str]]:
    """The model files to check, sorted and without repeats, and the directories that held none."""
    files: dict[str, None] = {}
    empty: list[str] = []
    for argument in arguments:
        path = Path(argument)
        if path.is_dir():
            inside = _walk(path)
            if not inside:
                empty.append(argument)
            files.update((str(p), None) for p in inside)
        else:
            files[argument] = None
    return sorted(files), empty

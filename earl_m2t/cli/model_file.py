"""Writing a model file that its user edits afterwards (convert's and import's output)."""

from __future__ import annotations

import sys
from pathlib import Path

from earl_m2t.output import OutputError, write_files


def write_model_file(command: str, target: Path, content: bytes, force: bool, made_by: str) -> int:
    """Writes ``content`` to ``target`` atomically and returns the exit status. A file there with
    other content may hold hand edits: it is kept (exit 1) unless ``force``."""
    if not force and target.is_file() and target.read_bytes() != content:
        print(f"earl-m2t: {command}: {target} exists and differs from the {made_by}; nothing written "
              "(--force to replace it)", file=sys.stderr)
        return 1
    try:
        report = write_files(target.parent, {target.name: content})
    except OutputError as exc:
        print(f"earl-m2t: {exc}", file=sys.stderr)
        return 2
    for line in report.lines():
        print(line)
    return 0

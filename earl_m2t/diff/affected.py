"""``earl-m2t diff --affected OUT_DIR --target T``: the files a model change touches in an
output folder, found by rendering both models in memory (nothing is written).

Generated files are compared between the two renderings: rewritten, newly generated, or no
longer generated (gen keeps such files; it never deletes). User files are compared with
the folder: created by the next ``gen`` (only the new model has them and the folder does
not), or orphaned (only the old model has them, and the folder has them as earl-m2t wrote
them). The source map (``.earl-trace.json``), which ``gen`` rewrites along with the files it
maps, is not listed.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from earl_m2t.gen import render
from earl_m2t.gen.rendered import USER_FILE_MARKER, Rendered
from earl_m2t.model.elements import EarlModel
from earl_m2t.output import written_by_earl_m2t


@dataclass(frozen=True)
class AffectedFile:
    """What the next ``gen`` does to a file. ``action``: ``rewrites`` (a generated file whose
    content changes), ``generates`` (a generated file the new model adds), ``drops`` (a
    generated file the new model no longer produces; gen keeps it), ``adds`` (a user file the
    next gen creates), ``orphans`` (a user file the new model no longer produces; gen keeps it)."""

    action: str
    path: str  # relative to the output folder, POSIX form


def affected_files(old: EarlModel | None, new: EarlModel | None, out_dir: Path, target: str) -> list[AffectedFile]:
    """Raises GenError when a model cannot be generated."""
    before = render(old, target) if old is not None else Rendered({}, {})
    after = render(new, target) if new is not None else Rendered({}, {})
    found: list[AffectedFile] = []
    for path in sorted(set(before.generated) | set(after.generated)):
        if path not in before.generated:
            found.append(AffectedFile("generates", path))
        elif path not in after.generated:
            found.append(AffectedFile("drops", path))
        elif bytes(before.generated[path]) != bytes(after.generated[path]):
            found.append(AffectedFile("rewrites", path))
    for path in sorted(set(before.user) | set(after.user)):
        existing = out_dir / path
        if path not in before.user and not existing.exists():
            found.append(AffectedFile("adds", path))
        elif path not in after.user and existing.is_file() and written_by_earl_m2t(existing, USER_FILE_MARKER):
            found.append(AffectedFile("orphans", path))
    return found

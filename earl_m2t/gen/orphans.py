"""What ``gen`` reports as orphaned in an output folder: files an earlier run wrote (known by
their first line) that the model no longer produces. They are reported and kept, never
deleted. Which of these a target looks for is its ``orphans`` entry in ``transforms/targets.toml``."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path, PurePosixPath

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.rendered import DOT_FILE_MARKER, MSG_FILE_MARKER, USER_FILE_MARKER, Rendered
from earl_m2t.output import written_by_earl_m2t

#: What a diagram may be rendered to, beside its source.
IMAGE_SUFFIXES = (".svg", ".png")

OrphanFinder = Callable[[Path, Rendered], tuple[str, ...]]


def find_orphans(out_dir: Path, produced: set[str]) -> tuple[str, ...]:
    """User files under ``out_dir/user`` (marked as created by earl-m2t) not in ``produced``."""
    found: list[str] = []
    for folder, _dirs, names in os.walk(out_dir / "user", followlinks=False):
        for name in names:
            path = Path(folder) / name
            relative = PurePosixPath(path.relative_to(out_dir).as_posix())
            if str(relative) not in produced and written_by_earl_m2t(path, USER_FILE_MARKER):
                found.append(str(relative))
    return tuple(sorted(found))


def find_stale_messages(out_dir: Path, produced: set[str]) -> tuple[str, ...]:
    """Generated messages (``*/msg/*.msg`` starting with the marker) not in ``produced``."""
    return tuple(relative for path in sorted(out_dir.glob("*/msg/*.msg"))
                 if (relative := path.relative_to(out_dir).as_posix()) not in produced
                 and written_by_earl_m2t(path, MSG_FILE_MARKER))


def find_stale_diagrams(out_dir: Path, produced: set[str], folder: str = "") -> tuple[str, ...]:
    """Diagrams in ``out_dir/folder`` that earl-m2t wrote (a ``.dot`` starting with the
    marker) and that are not in ``produced``, with their images: the diagrams of elements
    renamed or removed since."""
    found: list[str] = []
    for source in sorted((out_dir / folder).glob("*.dot")):
        relative = f"{folder}{source.name}"
        if relative not in produced and written_by_earl_m2t(source, DOT_FILE_MARKER):
            found.append(relative)
            found.extend(f"{folder}{source.stem}{suffix}" for suffix in IMAGE_SUFFIXES
                         if source.with_suffix(suffix).is_file() and f"{folder}{source.stem}{suffix}" not in produced)
    return tuple(found)


_FINDERS: dict[str, OrphanFinder] = {
    "user-files": lambda out_dir, rendered: find_orphans(out_dir, set(rendered.user)),
    "ros-messages": lambda out_dir, rendered: find_stale_messages(out_dir, set(rendered.generated)),
    "diagrams": lambda out_dir, rendered: find_stale_diagrams(out_dir, set(rendered.generated)),
}


def orphan_finder(policy: str) -> OrphanFinder:
    """The finder of an ``orphans`` entry of ``transforms/targets.toml``. Raises GenError."""
    finder = _FINDERS.get(policy)
    if finder is None:
        raise GenError(f"transforms/targets.toml: unknown orphans {policy!r} (one of {', '.join(_FINDERS)})")
    return finder


def orphans_of(finders: tuple[OrphanFinder, ...], out_dir: Path, rendered: Rendered) -> tuple[str, ...]:
    """Everything the finders report, sorted."""
    return tuple(sorted(path for find in finders for path in find(out_dir, rendered)))

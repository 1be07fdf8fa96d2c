"""The targets of ``earl-m2t gen`` as ``transforms/targets.toml`` declares them.

Kept apart from :mod:`earl_m2t.gen` so that the command line can list the targets without
importing Jinja and the views; :mod:`earl_m2t.gen.declared` adds each target's renderer."""

from __future__ import annotations

import tomllib
from functools import cache
from typing import NamedTuple

from earl_m2t import resources


class TargetInfo(NamedTuple):
    name: str
    help: str  # what comes out, for ``earl-m2t gen --help``
    doc: str  # the page that documents the target
    renderer: str  # the module of earl_m2t/gen/targets/ that renders it
    orphans: tuple[str, ...]  # what ``gen`` reports as orphaned in the output folder
    variable_structure: bool  # it runs a model with configurations (switches between them)


@cache
def gen_targets() -> tuple[TargetInfo, ...]:
    """Every target of ``earl-m2t gen``, in the order of ``transforms/targets.toml``."""
    path = resources.data_dir("transforms") / "targets.toml"
    table = tomllib.loads(path.read_text(encoding="utf-8"))
    return tuple(TargetInfo(name, str(entry["help"]), str(entry["doc"]), str(entry["renderer"]),
                            tuple(str(policy) for policy in entry["orphans"]),
                            bool(entry.get("variable_structure", True)))
                 for name, entry in table.items())

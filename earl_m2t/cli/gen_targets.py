"""The names of the ``earl-m2t gen`` targets, read from ``transforms/targets.toml``.

Kept apart from :mod:`earl_m2t.gen.generate` so that the command line can list the targets
without importing Jinja and the views."""

from __future__ import annotations

import tomllib
from functools import cache
from typing import NamedTuple

from earl_m2t import resources


class TargetInfo(NamedTuple):
    name: str
    help: str
    doc: str


@cache
def gen_targets() -> tuple[TargetInfo, ...]:
    """Every target of ``earl-m2t gen``, in the order of ``transforms/targets.toml``."""
    path = resources.data_dir("transforms") / "targets.toml"
    table = tomllib.loads(path.read_text(encoding="utf-8"))
    return tuple(TargetInfo(name, str(entry["help"]), str(entry["doc"])) for name, entry in table.items())

"""The targets of ``earl-m2t gen`` as declared: each entry of ``transforms/targets.toml``
(:mod:`earl_m2t.gen_targets`) with the renderer its ``renderer`` names (the ``RENDERER`` of
that module of :mod:`earl_m2t.gen.targets`) and the finders of what its ``orphans`` lists."""

from __future__ import annotations

import importlib
from dataclasses import dataclass

from earl_m2t.gen import targets as renderer_modules
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.orphans import OrphanFinder, orphan_finder
from earl_m2t.gen.target import Renderer
from earl_m2t.gen_targets import gen_targets


@dataclass(frozen=True)
class GenTarget:
    name: str  # also its folder transforms/NAME: its target.toml and templates
    renderer: Renderer
    orphans: tuple[OrphanFinder, ...]
    variable_structure: bool = True  # it runs a model with configurations


def declared_target(name: str) -> GenTarget:
    """The target ``name`` of ``transforms/targets.toml``. Raises GenError."""
    entries = {entry.name: entry for entry in gen_targets()}
    entry = entries.get(name)
    if entry is None:
        raise GenError(f"unknown target {name!r} (one of {', '.join(entries)})")
    module = importlib.import_module(f"{renderer_modules.__name__}.{entry.renderer}")
    renderer = getattr(module, "RENDERER", None)
    if not isinstance(renderer, Renderer):
        raise GenError(f"transforms/targets.toml: {module.__name__} declares no RENDERER for the target {name!r}")
    return GenTarget(name, renderer, tuple(orphan_finder(policy) for policy in entry.orphans),
                     entry.variable_structure)

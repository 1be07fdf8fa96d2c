"""The ``diagrams`` and ``diagrams-png`` targets: a ``.dot`` per diagram of
:mod:`earl_m2t.gen.diagrams`, rendered to the formats the target's ``target.toml`` lists
(``.svg``; ``diagrams-png`` also ``.png``) beside it."""

from __future__ import annotations

from earl_m2t.gen.diagrams import diagram_files, render_diagrams
from earl_m2t.gen.rendered import Rendered
from earl_m2t.gen.target import Renderer, TargetRun
from earl_m2t.gen.targets import tables


def _render(run: TargetRun) -> Rendered:
    formats = tuple(str(f) for f in run.spec.get("formats", ["svg"]))
    rendered = render_diagrams(run.model, formats, tables=run.views.get(tables.VIEW), templates=run.templates,
                               strict=run.strict)
    return Rendered(diagram_files(rendered), {})


RENDERER = Renderer(views=(tables.VIEW,), render=_render)

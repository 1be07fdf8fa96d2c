"""The diagrams of a model: DOT text from the templates of ``transforms/diagrams/``, rendered
by Graphviz ``dot`` (:mod:`earl_m2t.gen.dot`).

Used by ``earl-m2t gen --target diagrams`` (``.dot`` and ``.svg`` per diagram) and
``--target diagrams-png`` (also ``.png``), both :mod:`earl_m2t.gen.targets.diagrams`, and by
``earl-m2t report``. A warning of ``dot`` is an error unless ``strict`` is off (``gen --force``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import jinja2

from earl_m2t.gen.dot import DotError, html_label_text, run_dot
from earl_m2t.gen.engine import environment, load_target
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.rendered import DOT_FILE_MARKER
from earl_m2t.gen.views.diagrams import Diagram, build_diagrams
from earl_m2t.gen.views.tables import SpecTables, build_tables
from earl_m2t.model.elements import EarlModel

TARGET = "diagrams"


@dataclass(frozen=True)
class RenderedDiagram:
    diagram: Diagram
    source: bytes  # the DOT text
    images: dict[str, bytes]  # format -> bytes
    warnings: tuple[str, ...]  # what dot said about it


def dot_environment(templates: Path | None = None) -> jinja2.Environment:
    env = environment(TARGET, templates)
    max_chars = int(load_target(TARGET)["label_max_chars"])
    env.filters["h"] = lambda text: html_label_text(text, max_chars)
    return env


def diagram_sources(model: EarlModel, tables: SpecTables | None = None,
                    templates: Path | None = None) -> tuple[tuple[Diagram, bytes], ...]:
    """Every diagram of the model with its DOT text, in model order."""
    tables = tables or build_tables(model)
    names = load_target(TARGET)["templates"]
    env = dot_environment(templates)
    sources = []
    for diagram in build_diagrams(model, tables):
        source = render_template(env, names[diagram.kind], **diagram.context)
        if not source.startswith(DOT_FILE_MARKER):
            raise GenError(f"template {names[diagram.kind]} must start with {DOT_FILE_MARKER.decode()!r}")
        sources.append((diagram, source))
    return tuple(sources)


def render_diagrams(model: EarlModel, formats: tuple[str, ...] = ("svg",), tables: SpecTables | None = None,
                    templates: Path | None = None, strict: bool = True) -> tuple[RenderedDiagram, ...]:
    """Every diagram rendered by ``dot`` to ``formats``. Raises DotError (with ``strict``, also
    when dot warns)."""
    rendered = []
    for diagram, source in diagram_sources(model, tables, templates):
        images: dict[str, bytes] = {}
        warnings: list[str] = []
        for fmt in formats:
            result = run_dot(source, fmt, f"{diagram.name}.dot")
            images[fmt] = result.output
            warnings.extend(w for w in result.warnings if w not in warnings)
        if warnings and strict:
            raise DotError(f"dot warned on {diagram.name}.dot: {warnings[0]} (--force to write it anyway)")
        rendered.append(RenderedDiagram(diagram, source, images, tuple(warnings)))
    return tuple(rendered)


def diagram_files(rendered: tuple[RenderedDiagram, ...], folder: str = "") -> dict[str, bytes]:
    """``{path: bytes}`` of the sources and images, under ``folder`` (e.g. ``diagrams/``)."""
    files: dict[str, bytes] = {}
    for item in rendered:
        files[f"{folder}{item.diagram.name}.dot"] = item.source
        for fmt, content in item.images.items():
            files[f"{folder}{item.diagram.name}.{fmt}"] = content
    return files

"""The ``markdown`` target (``transforms/markdown/``): the paper-style tables of
:mod:`earl_m2t.gen.views.tables` as one Markdown file."""

from __future__ import annotations

import re

from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.rendered import Rendered
from earl_m2t.gen.target import Renderer, TargetRun
from earl_m2t.gen.targets import tables

_SPECIAL = re.compile(r"([\\`*_\[\]<>|#])")


def escape_markdown(text: object) -> str:
    """Text for a Markdown table cell: Markdown's special characters escaped, on one line."""
    return _SPECIAL.sub(r"\\\1", " ".join(str(text).split()))


def code_span(text: object) -> str:
    """Text as a code span in a table cell ("" stays empty); ``|`` is escaped as tables need."""
    value = " ".join(str(text).split())
    if not value:
        return ""
    fence = "`" * (max((len(run) for run in re.findall("`+", value)), default=0) + 1)
    pad = " " if value.startswith("`") or value.endswith("`") else ""
    return f"{fence}{pad}{value}{pad}{fence}".replace("|", "\\|")


def _render(run: TargetRun) -> Rendered:
    env = run.environment()
    env.filters["md"] = escape_markdown
    env.filters["code"] = code_span
    specification = run.views.get(tables.VIEW)
    files = {path: render_template(env, template, t=specification)
             for template, path in sorted(run.spec["templates"].items())}
    return Rendered(files, {})


RENDERER = Renderer(views=(tables.VIEW,), render=_render)

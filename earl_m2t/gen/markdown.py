"""``earl-m2t gen --target markdown``: the paper-style tables of
:mod:`earl_m2t.gen.views.tables` as one Markdown file (``transforms/markdown/``)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

from earl_m2t.gen.engine import environment, load_target, render as render_template
from earl_m2t.gen.views.tables import build_tables
from earl_m2t.model.elements import EarlModel

if TYPE_CHECKING:
    from earl_m2t.gen.generate import Rendered

TARGET = "markdown"
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


def render_target(model: EarlModel, templates: Path | None, strict: bool) -> Rendered:
    from earl_m2t.gen.generate import Rendered

    env = environment(TARGET, templates)
    env.filters["md"] = escape_markdown
    env.filters["code"] = code_span
    tables = build_tables(model)
    files = {path: render_template(env, template, t=tables)
             for template, path in sorted(load_target(TARGET)["templates"].items())}
    return Rendered(files, {})

"""An EARL model as SysML v2 text, rendered from ``transforms/sysml/templates/``."""

from __future__ import annotations

import jinja2

from earl_m2t import resources
from earl_m2t.convert.view import model_view
from earl_m2t.model.elements import EarlModel

TEMPLATE = "model.sysml.j2"


def _environment() -> jinja2.Environment:
    folder = resources.data_dir("transforms") / "sysml" / "templates"
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(folder)),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        autoescape=False,
    )


def to_sysml(model: EarlModel) -> str:
    """The SysML v2 text of a lifted model: reading it back gives the same EARL model, its LTL
    properties (for ``earl-m2t verify``) included."""
    return _environment().get_template(TEMPLATE).render(**model_view(model))

"""Render the profile with the Jinja2 templates of ``transforms/profile/``."""

from __future__ import annotations

import tomllib
from functools import cache
from pathlib import Path

import jinja2

from earl_m2t import resources
from earl_m2t.profile import load_profile
from earl_m2t.profile_export.formats import CONTEXTS, FORMATS, Target
from earl_m2t.profile_export.spec import ProfileExportError, profile_spec
from earl_m2t.profile_types import Profile

__all__ = ["FORMATS", "export_profile", "load_targets", "transforms_dir"]

_REQUIRED = ("title", "template", "output")
_OPTIONAL = ("uri", "version")


def transforms_dir() -> Path:
    """``transforms/profile``: target.toml and the templates."""
    return resources.data_dir("transforms") / "profile"


@cache
def load_targets() -> dict[str, Target]:
    """The formats of ``transforms/profile/target.toml``. Raises ProfileExportError."""
    path = transforms_dir() / "target.toml"
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise ProfileExportError(f"{path}: {error}") from None
    tables = data.get("formats", {})
    if sorted(tables) != sorted(FORMATS):
        raise ProfileExportError(f"{path}: [formats] must define exactly {', '.join(FORMATS)}")
    targets = {}
    for name in FORMATS:
        table = tables[name]
        missing = [key for key in _REQUIRED if not isinstance(table.get(key), str)]
        unknown = sorted(set(table) - set(_REQUIRED) - set(_OPTIONAL))
        if missing or unknown:
            problem = f"missing {', '.join(missing)}" if missing else f"unknown {', '.join(unknown)}"
            raise ProfileExportError(f"{path}: [formats.{name}]: {problem}")
        targets[name] = Target(name=name, **{k: str(v) for k, v in table.items()})
    return targets


_XML_ESCAPES = str.maketrans(
    {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;",
     "\n": "&#xA;", "\r": "&#xD;", "\t": "&#x9;"}
)


def xml_escape(value: object) -> str:
    """Every ``{{ value }}`` of a template, escaped for XML text and for attribute values in
    either quote style (line breaks as character references, so attributes keep them).
    ``None`` reaching a template is a bug in the data preparation, never written."""
    if value is None:
        raise ProfileExportError("a template printed a missing (None) value")
    return str(value).translate(_XML_ESCAPES)


@cache
def _environment() -> jinja2.Environment:
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(transforms_dir())),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,  # every value goes through xml_escape instead (finalize)
        finalize=xml_escape,
    )


def export_profile(format_name: str, profile: Profile | None = None) -> dict[str, bytes]:
    """The files of ``format_name`` for ``profile`` (default: profiles/earl.sysml):
    ``{file name: UTF-8 bytes}``. Raises ProfileExportError (and ProfileError when the
    profile file cannot be loaded)."""
    targets = load_targets()
    if format_name not in targets:
        raise ProfileExportError(f"unknown profile format {format_name!r} (one of {', '.join(FORMATS)})")
    target = targets[format_name]
    spec = profile_spec(profile if profile is not None else load_profile())
    context = CONTEXTS[format_name](spec, target)
    try:
        template = _environment().get_template(target.template)
    except jinja2.TemplateNotFound:
        raise ProfileExportError(f"template {target.template} is missing from {transforms_dir()}") from None
    return {target.output: template.render(context).encode("utf-8")}

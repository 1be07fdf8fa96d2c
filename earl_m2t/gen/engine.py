"""The Jinja2 environment of a target and its ``target.toml``.

Templates get plain data from the target's view and only format it: ``StrictUndefined``
(a missing value is a bug, never an empty string), ``keep_trailing_newline``, and a user
template folder searched before the built-in one, so any template can be overridden.
Rendering records which model element each output line comes from
(:mod:`earl_m2t.gen.tracing`): :func:`render` returns ``TracedBytes``.
"""

from __future__ import annotations

import functools
import tomllib
from pathlib import Path
from typing import Any

import jinja2

from earl_m2t import resources
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.tracing import TracingEnvironment, file_element, strip_markers, traced_bytes


def target_dir(target: str) -> Path:
    """``transforms/<target>``."""
    folder = resources.data_dir("transforms") / target
    if not (folder / "target.toml").is_file():
        raise GenError(f"unknown target {target!r}")
    return folder


def load_target(target: str) -> dict[str, Any]:
    """The parsed ``target.toml`` of a target. Raises GenError."""
    path = target_dir(target) / "target.toml"
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise GenError(f"{path}: {error}") from None


class _CompiledTemplates(jinja2.BytecodeCache):
    """Templates compiled once per process and shared by the environments of :func:`environment`
    of one class (the class decides how output is finalized, which the compiled code holds; the
    options are the same for all). Jinja keys a template by its file and checks the checksum of
    its text, so a user template or an edited file is compiled anew."""

    def __init__(self) -> None:
        self._code: dict[str, bytes] = {}

    def load_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        code = self._code.get(bucket.key)
        if code is not None:
            bucket.bytecode_from_string(code)

    def dump_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        self._code[bucket.key] = bucket.bytecode_to_string()


@functools.cache
def _compiled_templates(environment_class: type[jinja2.Environment]) -> _CompiledTemplates:
    return _CompiledTemplates()


def environment(target: str, user_templates: Path | None = None) -> jinja2.Environment:
    """A fresh environment for a target's templates: its own filters and globals, the compiled
    templates shared (a process that generates many times parses each template once)."""
    loaders: list[jinja2.BaseLoader] = []
    if user_templates is not None:
        if not user_templates.is_dir():
            raise GenError(f"template folder {user_templates} does not exist")
        loaders.append(jinja2.FileSystemLoader(str(user_templates)))
    loaders.append(jinja2.FileSystemLoader(str(target_dir(target) / "templates")))
    return TracingEnvironment(
        loader=jinja2.ChoiceLoader(loaders),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,
        bytecode_cache=_compiled_templates(TracingEnvironment),
    )


def render(env: jinja2.Environment, template: str, **context: Any) -> bytes:
    """The rendered bytes: a :class:`TracedBytes` that knows the elements of its lines."""
    try:
        return traced_bytes(strip_markers(env.get_template(template).render(**context)), file_element(context))
    except jinja2.TemplateNotFound:
        raise GenError(f"template {template} is missing") from None
    except jinja2.UndefinedError as error:
        raise GenError(f"template {template}: {error.message}") from None

"""The `gen` targets declared in transforms/targets.toml, the renderers of earl_m2t/gen/targets/,
the target folders and the documentation pages are one and the same set; a run builds each
view its renderer reads once, however many of the targets it includes read it."""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from earl_m2t import resources
from earl_m2t.api import load
from earl_m2t.cli.app import build_parser
from earl_m2t.gen import render
from earl_m2t.gen import targets as renderers
from earl_m2t.gen.declared import declared_target
from earl_m2t.gen.target import Renderer, View, Views
from earl_m2t.gen.targets import cpp, msg
from earl_m2t.gen_targets import gen_targets

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"


def test_every_listed_target_has_a_renderer_and_every_renderer_a_target() -> None:
    declared = {target.name: declared_target(target.name) for target in gen_targets()}
    assert all(isinstance(target.renderer, Renderer) for target in declared.values())
    modules = {info.name for info in pkgutil.iter_modules(renderers.__path__)
               if isinstance(getattr(importlib.import_module(f"{renderers.__name__}.{info.name}"), "RENDERER", None),
                             Renderer)}
    assert modules == {target.renderer for target in gen_targets()}


def test_every_target_has_its_folder_and_its_documentation_page() -> None:
    for target in gen_targets():
        assert (resources.data_dir("transforms") / target.name / "target.toml").is_file(), target.name
        assert (ROOT / target.doc).is_file(), target.doc


def test_the_command_line_offers_exactly_the_listed_targets() -> None:
    parser = build_parser()
    args = parser.parse_args(["gen", "model.uml", "-o", "out"])
    assert args.target == gen_targets()[0].name
    for target in gen_targets():
        assert parser.parse_args(["gen", "m.uml", "--target", target.name, "-o", "out"]).target == target.name


@pytest.mark.parametrize("target", ["ros", "orocos"])
def test_the_cpp_and_message_views_are_built_once_for_every_target_that_reads_them(
        target: str, monkeypatch: pytest.MonkeyPatch) -> None:
    builds: list[str] = []
    for module in (cpp, msg):
        def counting(*args: Any, build: Callable[..., Any] = module.build_view, name: str = module.__name__) -> Any:
            builds.append(name)
            return build(*args)

        monkeypatch.setattr(module, "build_view", counting)
    render(load(SAMPLE).model, target)
    assert sorted(builds) == [cpp.__name__, msg.__name__]


def test_a_renderer_reads_only_the_views_it_declares() -> None:
    declared = View("declared", lambda views: 1)
    undeclared = View("undeclared", lambda views: 2)
    views = Views(load(SAMPLE).model, True, (declared,))
    assert views.get(declared) == 1
    with pytest.raises(LookupError):
        views.get(undeclared)


def test_a_target_declared_without_variable_structure_refuses_a_model_with_configurations() -> None:
    """``variable_structure = false`` in transforms/targets.toml (for a target that cannot run
    a switch yet): gen refuses such a model in one line rather than generate one that never
    switches. Every target switches today, so the entry is made here."""
    from dataclasses import replace

    from earl_m2t.gen.errors import GenError
    from earl_m2t.gen.generate import _render

    model = load(Path(__file__).parent / "fixtures" / "variability" / "handover.sysml").model
    refusing = replace(declared_target("cpp"), variable_structure=False)
    with pytest.raises(GenError, match=r"--target cpp does not switch configurations yet \(the model has useA, useB\)"):
        _render(refusing, model, None, True)

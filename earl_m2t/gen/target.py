"""What the code of a ``gen`` target is made of: the views of the model it reads and the
function that renders its files from them (a :class:`Renderer`, declared by a module of
:mod:`earl_m2t.gen.targets` that ``transforms/targets.toml`` names).

A view is built at most once per run, however many targets read it: the ``ros`` target
renders the ``cpp`` and ``msg`` targets' files from the same C++ and message views it reads
itself. A renderer may read only the views it declares.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Generic, TypeVar, cast

import jinja2

from earl_m2t.gen.engine import environment, load_target
from earl_m2t.gen.rendered import Rendered
from earl_m2t.model.elements import EarlModel

ViewT = TypeVar("ViewT")


@dataclass(frozen=True)
class View(Generic[ViewT]):
    """A view of the model, named; ``build`` makes it from the model and the views it reads."""

    name: str
    build: Callable[[Views], ViewT]


class Views:
    """The views of one run, each built on first use and then kept."""

    def __init__(self, model: EarlModel, strict: bool, declared: Iterable[View[Any]]) -> None:
        self.model = model
        self.strict = strict  # refuse names that cannot become names of the target or collide (off with --force)
        self._declared = frozenset(view.name for view in declared)
        self._built: dict[str, Any] = {}

    def get(self, view: View[ViewT]) -> ViewT:
        if view.name not in self._declared:
            raise LookupError(f"the view {view.name!r} is read but not among the renderer's views")
        if view.name not in self._built:
            self._built[view.name] = view.build(self)
        return cast(ViewT, self._built[view.name])


@dataclass(frozen=True)
class TargetRun:
    """One target rendered in a run: its name, its ``target.toml``, the user's template folder
    and the run's views."""

    name: str
    spec: dict[str, Any]
    templates: Path | None
    views: Views

    @property
    def model(self) -> EarlModel:
        return self.views.model

    @property
    def strict(self) -> bool:
        return self.views.strict

    def environment(self) -> jinja2.Environment:
        return environment(self.name, self.templates)

    def for_target(self, target: str) -> TargetRun:
        """The same run for another target, whose files this one includes."""
        return replace(self, name=target, spec=load_target(target))


@dataclass(frozen=True)
class Renderer:
    """The code of a target: the views it reads (those of the targets it includes too) and
    the function that renders its files."""

    views: tuple[View[Any], ...]
    render: Callable[[TargetRun], Rendered]

"""Values computed from a lifted model, kept for as long as the model lives.

Rules that share an expensive analysis (B006 and B007 the guard analysis of a subsystem) ask a
function of the model for it; the function computes it once per model. The model stays a
frozen value: nothing is written into it, and a value kept here must not refer to the model
(it would keep the model alive).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Generic, TypeVar

from earl_m2t.model.elements import EarlModel

T = TypeVar("T")


class PerModel(Generic[T]):
    """``make(model)``, computed on the first call for a model and returned again after."""

    def __init__(self, make: Callable[[EarlModel], T]) -> None:
        self._make = make
        self._values: dict[int, T] = {}

    def __call__(self, model: EarlModel) -> T:
        key = id(model)
        found = self._values.get(key)
        if found is None:
            found = self._values[key] = self._make(model)
            weakref.finalize(model, self._values.pop, key, None)
        return found

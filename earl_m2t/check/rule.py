"""What a Python rule is: a function from the model to its :class:`Finding` s, registered
under its catalogue code with :func:`rule`.

The rule modules of :mod:`earl_m2t.check.rules` register themselves here when imported.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location


@dataclass(frozen=True, slots=True)
class Finding:
    """What a rule implementation reports; the engine adds code and severity."""

    message: str
    location: Location
    element: str = ""


RuleFunction = Callable[[EarlModel], Iterable[Finding]]
_REGISTERED: dict[str, RuleFunction] = {}


def rule(code: str) -> Callable[[RuleFunction], RuleFunction]:
    """Register the Python implementation of a catalogue rule."""

    def register(function: RuleFunction) -> RuleFunction:
        if code in _REGISTERED:
            raise ValueError(f"rule {code} is implemented twice")
        _REGISTERED[code] = function
        return function

    return register


def registered_rules() -> dict[str, RuleFunction]:
    """The implementations registered so far, by code."""
    return dict(_REGISTERED)

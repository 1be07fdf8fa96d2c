"""What a model says to earl-m2t itself in its comments and constraints: suppressions of rule
findings (``earl-m2t: ignore[C008] reason``) and LTL properties for ``verify``."""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.location import Location


@dataclass(frozen=True, slots=True)
class Suppression:
    """``earl-m2t: ignore[CODE, …] reason`` on an element: those rules' findings there are silenced."""

    codes: tuple[str, ...]  # as written: codes, rule names or a repository's rule names
    reason: str
    target: str  # xmi:id of the annotated element
    target_name: str  # "Connector 'commandLink'"
    location: Location  # of the comment


@dataclass(frozen=True, slots=True)
class LtlProperty:
    """An LTL formula over FSM states and primitive predicates (:mod:`earl_m2t.verify.ltl`)."""

    name: str  # the identifier SPIN knows it by
    text: str
    location: Location
    label: str = ""  # the name the model gives it

    @property
    def title(self) -> str:
        return self.label or self.name

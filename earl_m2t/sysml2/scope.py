"""Names in a SysML v2 model: its own definitions, the EARL concepts of the profile, and the
primitive types of the library package ScalarValues (``metamodel/grammar/sysml2-subset.toml``)."""

from __future__ import annotations

import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cache
from typing import Any

from earl_m2t.profile_types import Profile
from earl_m2t.resources import metamodel_path
from earl_m2t.sysml2.parser import identification, members, name_segments, rule
from earl_m2t.sysml2.subset import SUBSET_TABLE

PROFILE_PACKAGE = "EARL"

# The metadata definitions of EARL::Model and the stereotype that each applies: SysML v2 types
# metadata by metadata definitions, and the concepts are part, port and interface definitions.
METADATA_CONCEPTS = {"Priority": "FsmTransition", "Exclusive": "Exclusion", "Memory": "InternalMemory",
                     "Receive": "InputBuffer", "Activation": "FsmState", "Group": "BufferGroup",
                     "Ltl": "LtlProperty", "Structure": "Configuration", "Reconfigure": "FsmState",
                     "Quiescent": "FsmState", "AgentReactivation": "Agent",
                     "AgentHost": "Agent"}
# Metadata definitions without attributes that stand for a Boolean tag set to true
# (``@Quiescent;`` is the tag ``quiescent`` of «FsmState»).
METADATA_FLAGS = {"Quiescent": "quiescent"}
# Concepts whose metadata usage in a definition is an element of its own (a UML Constraint the
# block owns), not a stereotype applied to the definition it is written in.
OWNED_METADATA_CONCEPTS = frozenset({"Exclusion", "BufferGroup", "LtlProperty", "Configuration"})


@cache
def scalar_values() -> dict[str, str]:
    """ScalarValues type name → the primitive type it is (``Natural`` → ``Integer``)."""
    table = tomllib.loads(metamodel_path(*SUBSET_TABLE).read_text(encoding="utf-8"))
    return dict(table["scalar-values"])


@dataclass(frozen=True, slots=True)
class Resolved:
    """What a type or supertype name stands for: a definition of the model (``node``), a
    concept of the profile, a primitive type, or nothing known (``text`` as written)."""

    node: Any = None
    concept: str = ""
    primitive: str = ""
    text: str = ""


class Scope:
    """Resolves names by their last segment: a definition of the model first (unless the name
    is qualified by ``EARL``), then a concept of the profile, then a ScalarValues type."""

    def __init__(self, profile: Profile) -> None:
        self.profile = profile
        self.definitions: dict[str, list[Any]] = {}
        self.paths: dict[int, tuple[str, ...]] = {}  # id(definition) -> names of its owners and itself

    def index(self, elements: Iterable[Any], owners: tuple[str, ...] = ()) -> None:
        """Record the definitions of the packages and definitions below ``elements``."""
        for element in elements:
            kind = rule(element)
            name = identification(element)[1] if kind in ("Package", "Definition") else ""
            if kind == "Definition" and name:
                self.definitions.setdefault(name, []).append(element)
                self.paths[id(element)] = (*owners, name)
            if kind in ("Package", "Definition"):
                self.index(members(element), (*owners, name) if name else owners)

    def resolve(self, raw: str) -> Resolved:
        segments = name_segments(raw)
        name = segments[-1] if segments else raw
        local = self.definitions.get(name)
        if local and not (len(segments) > 1 and segments[0] == PROFILE_PACKAGE):
            # a qualified name picks the definition whose owners it names (P1::Status, P2::Status)
            qualified = [d for d in local if self.paths.get(id(d), ())[-len(segments):] == tuple(segments)]
            return Resolved(node=(qualified or local)[0])
        if name in self.profile.concepts:
            return Resolved(concept=name)
        if name in scalar_values():
            return Resolved(primitive=scalar_values()[name])
        return Resolved(text="::".join(segments) or raw)

    def metadata_concept(self, raw: str) -> str:
        """The EARL concept that metadata typed ``raw`` applies: the concept of a metadata
        definition of the profile (:data:`METADATA_CONCEPTS`), or a concept named itself."""
        segments = name_segments(raw)
        name = segments[-1] if segments else raw
        if name not in self.definitions and METADATA_CONCEPTS.get(name, "") in self.profile.concepts:
            return METADATA_CONCEPTS[name]
        return self.resolve(raw).concept

    def metadata_flags(self, raw: str) -> dict[str, str]:
        """The tags that metadata typed ``raw`` sets by being there (:data:`METADATA_FLAGS`)."""
        segments = name_segments(raw)
        name = segments[-1] if segments else raw
        flag = METADATA_FLAGS.get(name) if name not in self.definitions else None
        return {flag: "true"} if flag else {}

    def typing(self, usage: Any) -> Resolved | None:
        """What the first type of a usage (``x : T``) stands for; None when it has none."""
        declaration = getattr(usage, "declaration", None)
        for specialization in getattr(declaration, "specializations", None) or []:
            if rule(specialization) == "Typing":
                return self.resolve(specialization.types[0].name)
        return None

    def concept_of(self, node: Any) -> str:
        """The EARL concept a definition specialises, directly or through the model's definitions."""
        for current in self.ancestry(node):
            for supertype in getattr(current, "supertypes", None) or []:
                target = self.resolve(supertype)
                if target.concept:
                    return target.concept
        return ""

    def ancestry(self, node: Any) -> list[Any]:
        """A definition and the model's definitions it specialises, nearest first, each once."""
        found: list[Any] = []
        seen: set[int] = set()
        frontier = [node]
        while frontier:
            current = frontier.pop(0)
            if id(current) in seen:
                continue
            seen.add(id(current))
            found.append(current)
            for supertype in getattr(current, "supertypes", None) or []:
                target = self.resolve(supertype)
                if target.node is not None:
                    frontier.append(target.node)
        return found

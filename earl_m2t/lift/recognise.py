"""Which EARL concept an element stands for: stereotype, then generalisation, then name suffix.

The concepts, their abbreviations and their specialisation come from ``profiles/earl.sysml``.
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.profile_types import Profile
from earl_m2t.read.xmi import Element, ExternalRef, RawModel
from earl_m2t.stereotypes import Vocabulary

# Package names that hold the EARL *Model* blocks a user model specialises (paper Fig. 1).
MODEL_PACKAGE_NAMES = frozenset({"model", "earl", "earl model", "earlmodel", "earl::model"})
# Metaclasses of concepts that no classifier specialises (UML Constraints and Connectors do not
# generalise).
UNSPECIALISABLE_METACLASSES = frozenset({"Constraint", "Connector"})


@dataclass(frozen=True, slots=True)
class Recognition:
    concept: str  # concept name from the profile, "" when not recognised
    route: str  # "stereotype" | "generalisation" | "suffix" | ""
    conflict: str  # a description of disagreeing evidence, "" when none


NOT_RECOGNISED = Recognition("", "", "")


class Recogniser:
    """Recognises EARL concepts on raw XMI elements, caching per element id."""

    def __init__(self, raw: RawModel, profile: Profile, vocabulary: Vocabulary | None = None) -> None:
        self.raw = raw
        self.profile = profile
        self.vocabulary = vocabulary or Vocabulary(tuple(profile.concepts))
        self._cache: dict[int, Recognition] = {}

    def _concept_named(self, name: str) -> str:
        """The concept an EARL stereotype or EARL Model block of this name stands for
        (``ControlSubsystem``, or the authors' ``ContSubsys``)."""
        return self.vocabulary.earl_concept(name)

    # -- the three routes --------------------------------------------------------------------
    def by_stereotype(self, el: Element) -> tuple[str, dict[str, str]]:
        for app in self.raw.applied(el):
            if app.family == "earl":
                concept = self._concept_named(app.name)
            elif app.family == "other":
                concept = self.vocabulary.specialised_concept(app.profile_uri, app.name)
            else:
                continue
            if concept:
                return concept, app.tags
        return "", {}

    def tags(self, el: Element) -> dict[str, str]:
        return self.by_stereotype(el)[1]

    def by_generalisation(self, el: Element) -> str:
        seen: set[int] = set()
        frontier = [el]
        while frontier:
            current = frontier.pop()
            if id(current) in seen:
                continue
            seen.add(id(current))
            for gen in self.raw.children(current, "generalization"):
                general = self.raw.ref(gen, "general")
                if general is None:
                    continue
                if isinstance(general, ExternalRef):
                    concept = self._concept_named(general.fragment) or self._external_model_block_concept(general)
                    if self._generalisable(concept):
                        return concept
                    continue
                concept = self._model_block_concept(general)
                if self._generalisable(concept):
                    return concept
                frontier.append(general)
        return ""

    def _generalisable(self, concept: str) -> bool:
        """True for a concept a classifier can specialise: not one applied to a Constraint or a
        Connector (a model's own class named ``Configuration`` is no EARL configuration)."""
        found = self.profile.concepts.get(concept) if concept else None
        return found is not None and found.metaclass not in UNSPECIALISABLE_METACLASSES

    def _model_block_concept(self, el: Element) -> str:
        concept = self._concept_named(self.raw.name(el))
        if not concept:
            return ""
        owner = self.raw.owner(el)
        while owner is not None:
            if self.raw.name(owner).strip().lower() in MODEL_PACKAGE_NAMES:
                return concept
            owner = self.raw.owner(owner)
        return ""

    def _external_model_block_concept(self, ref: ExternalRef) -> str:
        """An EARL Model block in another resource, known by its qualified name (``EARL::Model::Agent``)."""
        owners = [segment.strip().lower() for segment in ref.path.split("::")[:-1]]
        if not any(owner in MODEL_PACKAGE_NAMES for owner in owners):
            return ""
        return self._concept_named(ref.name)

    def by_suffix(self, *names: str) -> str:
        for name in names:
            abbr = suffix_of(name)
            if abbr:
                concept = self.profile.by_abbreviation(abbr)
                if concept is not None:
                    return concept.name
        return ""

    # -- combined ----------------------------------------------------------------------------
    def recognise(self, el: Element, *extra_names: str) -> Recognition:
        """Recognise an element; ``extra_names`` are other names it goes by (a part's name)."""
        cached = self._cache.get(id(el)) if not extra_names else None
        if cached is not None:
            return cached
        stereotype, _ = self.by_stereotype(el)
        general = self.by_generalisation(el) if self.raw.uml_type(el) == "Class" else ""
        suffix = self.by_suffix(self.raw.name(el), *extra_names)
        found = [(c, r) for c, r in ((stereotype, "stereotype"), (general, "generalisation"), (suffix, "suffix")) if c]
        if not found:
            result = NOT_RECOGNISED
        else:
            concept, route = found[0]
            disagreeing = [
                f"{r} says {c}" for c, r in found[1:] if not self.compatible(concept, c)
            ]
            conflict = f"{route} says {concept} but " + ", ".join(disagreeing) if disagreeing else ""
            result = Recognition(concept, route, conflict)
        if not extra_names:
            self._cache[id(el)] = result
        return result

    def compatible(self, a: str, b: str) -> bool:
        return self.profile.is_a(a, b) or self.profile.is_a(b, a)

    def is_a(self, concept: str, ancestor: str) -> bool:
        return bool(concept) and self.profile.is_a(concept, ancestor)

    def abbreviation(self, concept: str) -> str:
        found = self.profile.concepts.get(concept)
        return (found.abbreviation or "") if found is not None else ""


def suffix_of(name: str) -> str:
    """The abbreviation a name ends with: ``manip/a`` → ``a``; a bare ``cs`` → ``cs``."""
    name = name.strip()
    if "/" in name:
        return name.rpartition("/")[2].strip()
    return name if name in ("cs",) else ""

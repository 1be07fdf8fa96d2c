"""The stereotype names that stand for EARL concepts beyond the concept names of the profile:
the EARL authors' short names (``metamodel/xmi/stereotype-names.toml``) and the stereotypes of
profiles that specialise EARL (Enterprise Architect ``<UMLProfile>`` and MDG Technology files)."""

from earl_m2t.stereotypes.vocabulary import SpecialisingProfile, Vocabulary, other_names

__all__ = ["SpecialisingProfile", "Vocabulary", "other_names"]

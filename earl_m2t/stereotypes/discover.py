"""The vocabulary a model is read with: the profiles given with ``--profile FILE`` and the EA
profile files found beside the model (``[specialising_profiles] beside_model`` of
``metamodel/xmi/stereotype-names.toml``)."""

from __future__ import annotations

import fnmatch
from collections.abc import Sequence
from pathlib import Path

from earl_m2t.read.safe_xml import parse_xml_file
from earl_m2t.stereotypes.ea_profile import is_profile_root, read_profile_file
from earl_m2t.stereotypes.vocabulary import SpecialisingProfile, Vocabulary, specialising_profile_settings


def profiles_beside(model: Path) -> list[Path]:
    """EA profile files in the model's folder, by name pattern and root element, sorted."""
    folder = model.parent
    patterns = [p.lower() for p in specialising_profile_settings()["beside_model"]]
    try:
        candidates = sorted(p for p in folder.iterdir() if p.is_file() and p != model)
    except OSError:
        return []
    found = []
    for candidate in candidates:
        if any(fnmatch.fnmatchcase(candidate.name.lower(), pattern) for pattern in patterns):
            if is_profile_root(parse_xml_file(candidate).getroot()):
                found.append(candidate)
    return found


def vocabulary_for(model: Path, concept_names: Sequence[str], given: Sequence[Path] = ()) -> Vocabulary:
    """The stereotype names a model is read with. Raises ModelReadError for a profile file that
    cannot be read."""
    base = Vocabulary(tuple(concept_names))
    files: list[Path] = []
    for path in [*given, *profiles_beside(model)]:
        if all(not _same(path, known) for known in files):
            files.append(path)
    profiles: list[SpecialisingProfile] = []
    for path in files:
        profiles.extend(read_profile_file(path, base.earl_concept))
    return Vocabulary(tuple(concept_names), tuple(profiles)) if profiles else base


def _same(a: Path, b: Path) -> bool:
    try:
        return a.resolve() == b.resolve()
    except OSError:
        return a == b

"""Stage 2: lift a raw XMI model into the typed EARL model."""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType

from earl_m2t.diagnostics import Diagnostic
from earl_m2t.lift.datatypes import DataTypeLifter
from earl_m2t.lift.directives import read_properties, read_suppressions
from earl_m2t.lift.recognise import Recogniser
from earl_m2t.lift.structure import StructureLifter
from earl_m2t.model.elements import EarlModel
from earl_m2t.profile import load_profile
from earl_m2t.profile_types import Profile
from earl_m2t.read.xmi import RawModel
from earl_m2t.stereotypes import Vocabulary


@dataclass(frozen=True)
class LiftResult:
    model: EarlModel
    diagnostics: tuple[Diagnostic, ...]


def lift(raw: RawModel, profile: Profile | None = None, vocabulary: Vocabulary | None = None) -> LiftResult:
    """Recognise the EARL concepts of a raw model and build the typed EARL model.

    ``vocabulary`` adds the stereotypes of profiles that specialise EARL (``--profile FILE``).
    """
    profile = profile or load_profile()
    recogniser = Recogniser(raw, profile, vocabulary)
    types = DataTypeLifter(raw)
    structure = StructureLifter(raw, recogniser, types)
    systems = structure.systems()
    model = EarlModel(
        file=raw.file,
        dialect=raw.dialect,
        name=raw.model_name,
        systems=tuple(systems),
        datatypes=MappingProxyType(dict(sorted(types.datatypes.items()))),
        has_earl_content=bool(systems) or structure.recognised_anything,
        suppressions=read_suppressions(raw),
        properties=read_properties(raw),
        datatype_namesakes=tuple(types.namesakes),
    )
    return LiftResult(model, tuple(raw.diagnostics) + tuple(types.diagnostics) + tuple(structure.diagnostics))

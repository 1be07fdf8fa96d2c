"""Reading a model file for the later stages: the file itself (:mod:`earl_m2t.read.xmi_index`) and
the other model files it references (:mod:`earl_m2t.read.resources`)."""

from __future__ import annotations

from pathlib import Path

from earl_m2t.read.resources import follow_references
from earl_m2t.read.xmi import RawModel
from earl_m2t.read.xmi_index import read_raw_model


def load_raw_model(path: Path, dialect: str | None = None) -> RawModel:
    """Read an XMI file or a ``.mdzip`` project into a :class:`RawModel`, with the model files it
    references (see :mod:`earl_m2t.read.resources`; what cannot be resolved is an R004 finding).

    ``dialect`` (a name of ``[dialects]`` in dialects.toml) overrides detection. Unreadable
    input raises :class:`ModelReadError <earl_m2t.diagnostics.ModelReadError>`.
    """
    raw = read_raw_model(path, dialect)
    follow_references(raw, path, dialect)
    return raw

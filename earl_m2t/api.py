"""The public entry points: load a model file, check it. Pure functions over a path."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from earl_m2t.check.engine import CheckOptions, check_model, deduplicate
from earl_m2t.diagnostics import Diagnostic
from earl_m2t.lift import lift
from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import EarlModel
from earl_m2t.shorten import shortened_words
from earl_m2t.sysml2.files import is_sysml2


@dataclass(frozen=True)
class Loaded:
    """A lifted model plus what reading and lifting found on the way."""

    model: EarlModel
    diagnostics: tuple[Diagnostic, ...]

    @property
    def properties(self) -> tuple[LtlProperty, ...]:
        """The model's «LtlProperty» constraints and ``earl-m2t: ltl`` comments (verify)."""
        return self.model.properties


def load(path: Path | str, dialect: str | None = None, profiles: Sequence[Path | str] = ()) -> Loaded:
    """Read and lift a model file; raises :class:`earl_m2t.diagnostics.ModelReadError` when unreadable.

    ``dialect`` (``papyrus``, ``cameo`` …, see ``metamodel/xmi/dialects.toml``) overrides detection.
    ``profiles`` are Enterprise Architect profile or MDG Technology files of profiles that
    specialise EARL; such files beside the model are read as well (docs/modelling-guide.md).
    """
    from earl_m2t.predicate.known import save as save_parsed_predicates
    from earl_m2t.profile import load_profile
    from earl_m2t.stereotypes.discover import vocabulary_for

    file = Path(path)
    vocabulary = vocabulary_for(file, tuple(load_profile().concepts), [Path(p) for p in profiles])
    if is_sysml2(file):
        from earl_m2t.sysml2.reader import read_sysml2  # loaded only when needed

        raw = read_sysml2(file)
    else:
        from earl_m2t.read.loader import load_raw_model  # loaded only for XMI, with the reader of referenced files

        raw = load_raw_model(file, dialect)
    result = lift(raw, vocabulary=vocabulary)
    save_parsed_predicates()
    return Loaded(result.model, result.diagnostics)


def check(path: Path | str, options: CheckOptions | None = None, dialect: str | None = None) -> list[Diagnostic]:
    """Every enabled diagnostic for one model file, sorted by location."""
    options = options or CheckOptions()
    loaded = load(path, dialect)
    return check_loaded(loaded, options)


def check_loaded(loaded: Loaded, options: CheckOptions) -> list[Diagnostic]:
    from earl_m2t.check.registry import catalogue
    from earl_m2t.check.suppress import apply_suppressions

    rules = catalogue()
    reader_findings = [
        Diagnostic(d.code, options.severity(rules[d.code]) if d.code in rules else d.severity, d.message,
                   d.location, d.element)
        for d in loaded.diagnostics
        if options.enabled(d.code)
    ]
    found = deduplicate(reader_findings + check_model(loaded.model, options))
    kept = apply_suppressions(found, loaded.model, options)
    return sorted((_readable(d) for d in kept), key=Diagnostic.sort_key)


def _readable(diagnostic: Diagnostic) -> Diagnostic:
    """Model values of any length (names, hrefs) shortened in the message and element path."""
    message, element = shortened_words(diagnostic.message), shortened_words(diagnostic.element)
    if message == diagnostic.message and element == diagnostic.element:
        return diagnostic
    return dataclasses.replace(diagnostic, message=message, element=element)

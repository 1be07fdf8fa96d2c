"""Predicate texts parsed before, kept between runs in the on-disk cache (:mod:`earl_m2t.cache`).

A model's conditions are mostly the same few hundred texts from one ``check`` to the next;
reading their trees back costs far less than loading the grammar (textX) and parsing them
again. The cache entry is keyed by the grammar file and earl-m2t's own modules, so a changed
grammar or parser never serves an old tree. :func:`save` writes the texts parsed since the
entry was read; it keeps at most ``_MAX_TEXTS`` texts (past that, only those of this run).
"""

from __future__ import annotations

from pathlib import Path

from earl_m2t.cache import read_cached, write_cached
from earl_m2t.predicate.ast import Expr
from earl_m2t.predicate.errors import PredicateSyntaxError
from earl_m2t.resources import metamodel_path

Parsed = Expr | PredicateSyntaxError

_ENTRY = "predicates"
_MAX_TEXTS = 2_000  # about 0.5 MB, read back in 10-20 ms; parsing them would take about 0.5 s


class _Known:
    def __init__(self) -> None:
        self.table: dict[str, Parsed] | None = None  # read from the cache on first use
        self.used: set[str] = set()
        self.added = False


_known = _Known()


def _grammar() -> Path:
    return metamodel_path("grammar", "predicate.tx")


def _table() -> dict[str, Parsed]:
    if _known.table is None:
        stored = read_cached(_ENTRY, _grammar())
        _known.table = stored if isinstance(stored, dict) else {}
    return _known.table


def parsed(text: str) -> Parsed:
    """The tree of ``text``, or the syntax error that stops it (as ``parse_predicate`` raises it)."""
    table = _table()
    _known.used.add(text)
    found = table.get(text)
    if found is not None:
        return found
    from earl_m2t.predicate.parser import parse_predicate  # the grammar only for a text not seen before

    result: Parsed
    try:
        result = parse_predicate(text)
    except PredicateSyntaxError as error:
        result = error
    table[text] = result
    _known.added = True
    return result


def save() -> None:
    """Write the texts parsed in this run to the cache, when there are new ones."""
    if not _known.added or _known.table is None:
        return
    table = _known.table
    if len(table) > _MAX_TEXTS:
        table = {text: table[text] for text in _known.used if text in table}
    write_cached(_ENTRY, _grammar(), table)
    _known.added = False

"""The permitted-link table of rule C002: the built-in one, or a model repository's own.

A configuration may replace ``metamodel/tables/permitted-links.toml`` (same shape); the
engine installs the replacement for the duration of one check with :func:`using_permitted_links`.
"""

from __future__ import annotations

import tomllib
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from functools import cache

from earl_m2t.resources import metamodel_path

LinkTable = Mapping[str, frozenset[tuple[str, str]]]
SCOPES = ("inter_subsystem", "inter_agent")
KINDS = frozenset({"cs", "ve", "re", "vr", "rr"})

_OVERRIDE: ContextVar[LinkTable | None] = ContextVar("permitted_links", default=None)


class LinkTableError(ValueError):
    """A permitted-link table of the wrong shape; the message names the offending key."""


def parse_link_table(data: Mapping[str, object],
                     base: LinkTable | None = None) -> dict[str, frozenset[tuple[str, str]]]:
    """Validate a table ``{scope: [[source kind, destination kind], …]}``; a scope left out keeps ``base``'s."""
    table = dict(base or {})
    for scope, pairs in data.items():
        if scope not in SCOPES:
            raise LinkTableError(f"unknown key '{scope}' (expected {' or '.join(SCOPES)})")
        if not isinstance(pairs, list):
            raise LinkTableError(f"'{scope}' must be a list of [source, destination] kind pairs")
        found = set()
        for pair in pairs:
            if not (isinstance(pair, list) and len(pair) == 2 and all(k in KINDS for k in pair)):
                raise LinkTableError(f"'{scope}': {pair!r} is not a pair of subsystem kinds "
                                     f"({', '.join(sorted(KINDS))})")
            found.add((pair[0], pair[1]))
        table[scope] = frozenset(found)
    missing = [scope for scope in SCOPES if scope not in table]
    if missing:
        raise LinkTableError(f"missing key '{missing[0]}'")
    return table


@cache
def builtin_permitted_links() -> dict[str, frozenset[tuple[str, str]]]:
    table = tomllib.loads(metamodel_path("tables", "permitted-links.toml").read_text("utf-8"))
    return parse_link_table(table)


def permitted_links() -> LinkTable:
    """The table in force: the configured one during :func:`using_permitted_links`, else the built-in one."""
    override = _OVERRIDE.get()
    return override if override is not None else builtin_permitted_links()


@contextmanager
def using_permitted_links(table: LinkTable | None) -> Iterator[None]:
    token = _OVERRIDE.set(table)
    try:
        yield
    finally:
        _OVERRIDE.reset(token)

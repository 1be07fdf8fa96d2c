"""The view of the paper-style tables (:mod:`earl_m2t.gen.views.tables`), which the
``diagrams``, ``diagrams-png`` and ``markdown`` targets read."""

from __future__ import annotations

from earl_m2t.gen.target import View, Views
from earl_m2t.gen.views.tables import SpecTables, build_tables


def _tables(views: Views) -> SpecTables:
    return build_tables(views.model)


VIEW = View("tables", _tables)

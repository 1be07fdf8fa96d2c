"""Traceability: the source map of an output folder (``.earl-trace.json``, written by ``gen``)
and ``earl-m2t trace``, which leads from a generated line to the model element it comes from."""

from earl_m2t.trace.sourcemap import TRACE_FILE, source_map, with_source_map

__all__ = ["TRACE_FILE", "source_map", "with_source_map"]

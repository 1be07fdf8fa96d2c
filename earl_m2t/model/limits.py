"""The numbers of a model earl-m2t takes at face value only up to a bound (docs/untrusted-models.md).

A model above one is refused with an R008 finding at the element, rather than expanded into
more instances, elements or queue slots than any robot controller needs (an input an attacker
or a mistyped digit makes enormous)."""

from __future__ import annotations

MAX_INSTANCES = 1024  # instances a replicated part, buffer or memory ([K]) stands for
MAX_ARRAY = 65_536  # elements of an array field of a dataType
MAX_QUEUE = 65_536  # values a queued Input Buffer holds (queueSize)
MAX_SECONDS = 31_536_000.0  # a period, timeout or switchTimeout: a year (in ns it fits a 64-bit integer)
MAX_EXPANSION = 10_000  # nodes a condition's replications (any K: …, all K: …) may expand to
MAX_OPERATORS = 10_000  # operators in one condition or expression (parsing cost grows faster than its length)
MAX_NESTING = 200  # levels of brackets, or prefix operators in a row, in text a parser descends into

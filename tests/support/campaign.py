"""How many runs each loaded campaign makes (a run or launch of a sample under a CPU hog per
core, checked for its sequence, its switches, its commands).

``EARL_CAMPAIGN_RUNS`` sets it; unset, a campaign makes ``FULL`` runs, the count the issues'
acceptance speaks of. ``./dev test`` (and so CI) sets ``SUITE`` runs, which keeps the suite within
its time while every campaign still runs loaded and can fail; ``./dev campaign`` runs every
campaign module with ``FULL`` runs. A search for a failure that a broken build must show (the
drain-skipping build) always tries up to ``FULL`` runs: it stops at the first failure it finds.
"""

from __future__ import annotations

import os

FULL = 50
SUITE = 10
VARIABLE = "EARL_CAMPAIGN_RUNS"


def loaded_runs() -> int:
    """The runs of a campaign: ``EARL_CAMPAIGN_RUNS`` (a positive whole number), else ``FULL``."""
    text = os.environ.get(VARIABLE, "").strip()
    if not text:
        return FULL
    if not text.isdigit() or int(text) < 1:
        raise ValueError(f"{VARIABLE}={text!r}: a positive whole number of runs")
    return int(text)


def long_runs(divisor: int) -> int:
    """The runs of a campaign whose every run takes long (tens of seconds under load): all of
    :func:`loaded_runs` in a full campaign, a ``divisor``-th of them (at least 2) in a shorter one."""
    runs = loaded_runs()
    return runs if runs >= FULL else max(2, runs // divisor)


#: Up to how many runs a search for an expected failure tries.
CATCH_ATTEMPTS = FULL

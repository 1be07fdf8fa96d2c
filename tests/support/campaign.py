"""How many runs each loaded campaign makes (a run or launch of a sample under a CPU hog per
core, checked for its sequence, its switches, its commands).

The campaigns, their counts and their known-bad variants are in ``campaigns.toml``.
``EARL_CAMPAIGN_RUNS`` chooses the count: ``suite`` (what ``./dev test``, and so CI, sets) the
table's ``suite`` runs, the fewest that still catch the campaign's known-bad variant; ``full``
or unset the table's ``full`` runs (``./dev campaign``, the counts the docs' figures were
measured with); a positive whole number that many runs for every campaign.

Each campaign has a known-bad variant, a build or model that breaks what the campaign exists to
catch (the drain skipped, a restarted agent instead of a resumed one, a one-shot command into a
latest-value input). Its test runs the variant under the same load for at most
:func:`catch_runs`, the runs the campaign itself makes, and fails unless the checks catch it:
a campaign shortened below what catches its variant fails in the suite, not silently.
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

VARIABLE = "EARL_CAMPAIGN_RUNS"
TABLE = Path(__file__).with_name("campaigns.toml")


@dataclass(frozen=True)
class Campaign:
    name: str
    tests: tuple[str, ...]  # pytest node ids (a parametrized test with its id, or all its cases)
    known_bad: str  # the node id of the known-bad variant's test
    suite: int
    full: int


@cache
def campaigns() -> dict[str, Campaign]:
    with TABLE.open("rb") as file:
        rows = tomllib.load(file)["campaign"]
    return {row["name"]: Campaign(row["name"], tuple(row["tests"]), row["known_bad"], row["suite"], row["full"])
            for row in rows}


def loaded_runs(name: str) -> int:
    """The runs of the campaign ``name``, as ``EARL_CAMPAIGN_RUNS`` chooses."""
    campaign = campaigns()[name]
    text = os.environ.get(VARIABLE, "").strip()
    if text in ("", "full"):
        return campaign.full
    if text == "suite":
        return campaign.suite
    if not text.isdigit() or int(text) < 1:
        raise ValueError(f"{VARIABLE}={text!r}: 'suite', 'full' or a positive whole number of runs")
    return int(text)


def catch_runs(name: str) -> int:
    """Up to how many runs the search for the known-bad variant's failure tries: the campaign's
    own :func:`loaded_runs`; the search stops at the first failure it finds."""
    return loaded_runs(name)

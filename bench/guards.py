"""How long the exact guard analysis (rules B006, B007) takes on a large FSM state.

    python bench/guards.py [--runs N]

Builds in memory one subsystem whose state ``hub`` has 30 outgoing transitions of equal
priority over 40 atoms (30 boolean fields, 5 ``newData`` terms, 5 comparisons, each behind a
primitive predicate, two of them declared exclusive) and times, as the median of ``--runs``
runs:

* ``guard analysis``: building the analysis (expand, encode) plus B006 on every pair of
  transitions (435 pairs) and B007, with counterexamples;
* ``parse + resolve (baseline)``: what the lift does with the same conditions for B008 and B005
  (parse each one, resolve its references), measured in the same run.

The ratio says what the exact analysis costs next to merely reading the conditions.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from earl_m2t.analysis.guards import GuardAnalysis  # noqa: E402
from earl_m2t.lift import conditions  # noqa: E402
from earl_m2t.model.elements import EarlModel, Subsystem  # noqa: E402
from tests.support.fsm_builder import build  # noqa: E402

ATOMS, TRANSITIONS = 40, 30
T = TypeVar("T")


def subsystem() -> tuple[EarlModel, Subsystem]:
    predicates: dict[str, str | None] = {}
    for i in range(30):
        predicates[f"flag{i}/pp"] = f"in/ib.msg.b{i}"
    for i in range(5):
        predicates[f"fresh{i}/pp"] = f"newData(in/ib.msg.b{i})"
    for i, (op, value) in enumerate([(">", 1), ("<=", 3), (">=", 5), ("<", 0.5), ("==", 2)]):
        predicates[f"range{i}/pp"] = f"in/ib.msg.v {op} {value}"
    names = [name.partition("/")[0] for name in predicates]
    assert len(names) == ATOMS
    transitions = []
    for t in range(TRANSITIONS):
        # a 5-bit mode code keeps most pairs apart; codes repeat past 26, so a few pairs overlap
        code = t % 26
        bits = [names[b] if code >> b & 1 else f"¬{names[b]}" for b in range(5)]
        extra = f"({names[5 + t % 25]} ∨ {names[30 + t % 10]} ∨ ¬{names[5 + (t * 7) % 25]})"
        transitions.append(("hub", f"s{t}", " ∧ ".join(bits + [extra]), 0))
    states: dict[str, tuple[str | None, str | None]] = {"hub": ("flag0 ∨ fresh1 ∨ range2", "flag29 ∧ range4")}
    states.update({f"s{t}": ("FALSE", None) for t in range(TRANSITIONS)})
    return build(predicates, states, transitions, exclusions=[("fresh0/pp", "fresh1/pp")], booleans=30)


def analyse(model: EarlModel, sub: Subsystem) -> tuple[int, bool, int]:
    analysis = GuardAnalysis(sub, model.datatypes)
    assert sub.fsm is not None
    hub = sub.fsm.states[0]
    overlaps = list(analysis.overlaps(hub))
    return len(overlaps), analysis.gap(hub) is not None, analysis.cnf.calls


def baseline(model: EarlModel, sub: Subsystem) -> int:
    conditions._parse.cache_clear()
    resolved = conditions.resolve_subsystem(sub, model.datatypes)
    return sum(len(condition.problems) for condition in resolved.conditions())


def _median(function: Callable[[], T], runs: int) -> tuple[float, T]:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args(argv)
    model, sub = subsystem()
    analyse(model, sub)  # warm up imports and the grammar
    base, problems = _median(lambda: baseline(model, sub), args.runs)
    took, (overlaps, gap, calls) = _median(lambda: analyse(model, sub), args.runs)
    assert problems == 0
    print(f"{ATOMS} atoms, {TRANSITIONS} transitions out of one state, median of {args.runs} runs")
    print(f"{'guard analysis (B006 + B007)':32s} {took * 1000:9.1f} ms   {overlaps} overlaps, gap: {gap}, "
          f"{calls} SAT calls")
    print(f"{'parse + resolve (baseline)':32s} {base * 1000:9.1f} ms")
    print(f"{'ratio analysis / baseline':32s} {took / base:9.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

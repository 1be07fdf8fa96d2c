"""Where one ``check`` spends its time and memory, phase by phase, in one process.

    python bench/phases.py bench/out/model_10mb.uml

Runs the stages of ``earl-m2t check`` one after the other (imports, EARL profile, predicate
grammar, OCL invariants, XML parse, id index, lift, rules) and prints, after each, the time
it took and the process's resident set size (``VmRSS``) and peak (``VmHWM``) from
``/proc/self/status`` (Linux). A diagnostic companion to ``bench/run.py``: the figures
that count are run.py's whole-process ones; this shows how they split.
"""

from __future__ import annotations

import gc
import sys
import time
from pathlib import Path

_T0 = time.perf_counter()


def _memory() -> tuple[float, float]:
    """(current, peak) resident set size in MB (10^6 bytes)."""
    values = {}
    with open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            key, _, rest = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                values[key] = int(rest.split()[0]) * 1024 / 1e6
    return values.get("VmRSS", 0.0), values.get("VmHWM", 0.0)


class _Clock:
    def __init__(self) -> None:
        self.last = _T0
        print(f"{'phase':28s} {'time (s)':>9s} {'RSS (MB)':>10s} {'peak (MB)':>10s}")

    def mark(self, label: str) -> None:
        now = time.perf_counter()
        rss, peak = _memory()
        print(f"{label:28s} {now - self.last:9.3f} {rss:10.1f} {peak:10.1f}", flush=True)
        self.last = time.perf_counter()


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1 or args[0].startswith("-"):
        print("usage: python bench/phases.py MODEL", file=sys.stderr)
        return 0 if args and args[0] in ("-h", "--help") else 2
    path = Path(args[0])
    gc.disable()  # as the command line runs (earl_m2t.cli.app.entry)
    clock = _Clock()

    import earl_m2t.cli.app  # noqa: F401  (what the command line imports)
    from earl_m2t.api import Loaded, check_loaded
    from earl_m2t.check.engine import CheckOptions, builtin_invariants
    from earl_m2t.check.registry import catalogue
    from earl_m2t.check.rules import python_rules
    from earl_m2t.lift import lift
    from earl_m2t.predicate import parse_predicate
    from earl_m2t.profile import load_profile
    from earl_m2t.read.safe_xml import parse_xml_file
    from earl_m2t.read.xmi_index import index_tree

    python_rules()
    catalogue()
    clock.mark("imports, rule registry")
    load_profile()
    clock.mark("EARL profile")
    parse_predicate("a/pp")
    clock.mark("predicate grammar")
    builtin_invariants()
    clock.mark("OCL invariants")
    tree = parse_xml_file(path)
    clock.mark("lxml parse")
    raw = index_tree(tree.getroot(), str(path))
    clock.mark("index (ids, stereotypes)")
    lifted = lift(raw)
    clock.mark("lift")
    diagnostics = check_loaded(Loaded(lifted.model, lifted.diagnostics), CheckOptions())
    clock.mark("rules")
    print(f"{len(diagnostics)} diagnostic(s); total {time.perf_counter() - _T0:.3f} s "
          "(without interpreter start-up and exit)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

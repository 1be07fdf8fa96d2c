"""Benchmark ``earl-m2t check`` against a bare lxml parse of the same file.

    python bench/run.py                 # 1, 10 and 100 MB models, 5 runs each
    python bench/run.py --quick         # 1 and 10 MB only
    python bench/run.py --sizes 10,100 --runs 3
    python bench/run.py --sizes 10,100 --versus ../other-checkout   # paired with another commit

Every measurement is a whole process started fresh (``subprocess``): its wall time from
start to exit, and its peak resident set size (``ru_maxrss`` of that child, from
``os.wait4``). Per model size it runs

* ``earl-m2t check FILE``: read, lift and check, as a user runs it;
* a baseline: a fresh interpreter that imports only ``lxml.etree`` and parses the file
  with the parser options earl-m2t uses (``huge_tree=True``, ``resolve_entities=False``,
  ``no_network=True``, no DTD, comments and PIs removed, no ID table);
* the floor: ``bench/one_pass.py FILE``, the same parse and one pass from Python over every
  element (its id, type, name and line into an index), leaving without freeing the tree as
  earl-m2t does: the least a checker written in Python over lxml costs;
* ``python -c pass``: the interpreter's own start-up, for context;
* with ``--versus DIR``: ``DIR/.venv/bin/earl-m2t check FILE``, the check of another checkout
  (another commit, set up with ``make setup`` there), interleaved with the others run by run,
  so that both commits' ratios to the same parse come from one run.

Before the models, the start-up row: ``earl-m2t --help`` against ``python -c pass``, run by
run interleaved, with the target for ``--help``.

It prints the medians, the ratios check/parse for time and memory, how those ratios
grow from the 10 MB to the 100 MB model, and the targets next to the figures. Models
missing from ``bench/out/`` are generated first with ``bench/generate.py --target-mb``.
Nothing is asserted; the script reports figures.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
OUT = BENCH / "out"

# The options of earl_m2t.read.safe_xml._parser, repeated here so that the baseline
# process imports nothing but lxml.
PARSE_SCRIPT = (
    "import sys\n"
    "from lxml import etree\n"
    "parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, dtd_validation=False,\n"
    "                         huge_tree=True, remove_comments=True, remove_pis=True, collect_ids=False)\n"
    "tree = etree.parse(sys.argv[1], parser)\n"
)

TARGET_TIME_RATIO = 2.0  # check / parse wall time, at 10 and 100 MB
TARGET_MEMORY_RATIO = 1.5  # check / parse peak RSS, at 10 and 100 MB
TARGET_GROWTH = 1.25  # (100 MB ratio) / (10 MB ratio)
TARGET_SMALL_SECONDS = 0.25  # check of the 1 MB model
TARGET_HELP_SECONDS = 0.06  # earl-m2t --help, wall, whole process
STARTUP_RUNS = 11  # the least number of start-up runs: they are short and noisy


@dataclass
class Sample:
    wall: float  # seconds
    rss: float  # MB (10^6 bytes)
    exit_code: int
    output: str


@dataclass
class Summary:
    wall: float  # median seconds
    rss: float  # median MB
    wall_min: float
    wall_max: float
    runs: int


def run_once(argv: list[str]) -> Sample:
    """Run ``argv`` as a fresh process; wall time and the peak RSS of that very process."""
    start = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, cwd=ROOT)
    assert proc.stdout is not None
    output = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)  # reaped by wait4; keep Popen consistent
    proc.stdout.close()
    # Linux reports ru_maxrss in KiB.
    return Sample(wall, usage.ru_maxrss * 1024 / 1e6, proc.returncode, output.decode("utf-8", "replace"))


def summarise(samples: list[Sample]) -> Summary:
    walls = [s.wall for s in samples]
    return Summary(statistics.median(walls), statistics.median(s.rss for s in samples), min(walls), max(walls),
                   len(samples))


def earl_m2t_command() -> list[str]:
    script = Path(sys.executable).parent / "earl-m2t"
    return [str(script)] if script.exists() else [sys.executable, "-m", "earl_m2t"]


def model_path(size_mb: int) -> Path:
    return OUT / f"model_{size_mb}mb.uml"


def ensure_model(size_mb: int) -> Path:
    path = model_path(size_mb)
    if not path.exists():
        print(f"generating {path.relative_to(ROOT)} ...", flush=True)
        subprocess.run([sys.executable, str(BENCH / "generate.py"), "--target-mb", str(size_mb), "-o", str(path)],
                       check=True, cwd=ROOT)
    return path


def measure(size_mb: int, runs: int, check_cmd: list[str], versus_cmd: list[str] | None = None) -> dict:
    path = ensure_model(size_mb)
    rel = str(path.relative_to(ROOT))
    check_argv = [*check_cmd, "check", rel]
    parse_argv = [sys.executable, "-c", PARSE_SCRIPT, rel]
    floor_argv = [sys.executable, str(BENCH / "one_pass.py"), rel]
    versus_argv = [*versus_cmd, "check", str(path)] if versus_cmd else None
    # One untimed round first: the file is then in the page cache for every timed run.
    warm = run_once(check_argv)
    run_once(parse_argv)
    run_once(floor_argv)
    clean = warm.exit_code == 0 and "0 error(s), 0 warning(s)" in warm.output
    if versus_argv:
        clean = clean and run_once(versus_argv).exit_code == 0
    checks, parses, floors, versus = [], [], [], []
    for _ in range(runs):  # interleaved, so that drift hits all alike
        checks.append(run_once(check_argv))
        parses.append(run_once(parse_argv))
        floors.append(run_once(floor_argv))
        if versus_argv:
            versus.append(run_once(versus_argv))
    for sample in checks + parses + floors + versus:
        if sample.exit_code != 0:
            clean = False
    return {
        "versus": summarise(versus) if versus else None,
        "size_mb": size_mb,
        "file": rel,
        "file_mb": path.stat().st_size / 1e6,
        "clean": clean,
        "check_output": warm.output.strip().splitlines()[-1:] if warm.output.strip() else [],
        "check": summarise(checks),
        "parse": summarise(parses),
        "floor": summarise(floors),
    }


def measure_startup(runs: int, check_cmd: list[str]) -> tuple[Summary, Summary]:
    """``python -c pass`` and ``earl-m2t --help``, interleaved run by run."""
    bare_argv, help_argv = [sys.executable, "-c", "pass"], [*check_cmd, "--help"]
    run_once(bare_argv)  # untimed: the interpreter's and the package's files into the page cache
    run_once(help_argv)
    bare, helps = [], []
    for _ in range(runs):
        bare.append(run_once(bare_argv))
        helps.append(run_once(help_argv))
    return summarise(bare), summarise(helps)


def report_startup(startup: Summary, help_run: Summary) -> None:
    print()
    print(f"== start-up, median of {help_run.runs} runs (interleaved) ==")
    print(f"   {'':24s} {'wall (s)':>9s} {'min-max (s)':>15s}")
    for label, row in (("python -c pass", startup), ("earl-m2t --help", help_run)):
        print(f"   {label:24s} {row.wall:9.3f} {row.wall_min:7.3f}-{row.wall_max:.3f}")
    ok = "met" if help_run.wall <= TARGET_HELP_SECONDS else "NOT met"
    print(f"   earl-m2t --help: {help_run.wall:.3f} s, {help_run.wall / startup.wall:.1f}× python -c pass  "
          f"(target ≤ {TARGET_HELP_SECONDS} s: {ok})")


def fmt_ratio(value: float, target: float | None) -> str:
    text = f"{value:5.2f}×"
    if target is None:
        return text
    return f"{text}  (target ≤ {target:g}×: {'met' if value <= target else 'NOT met'})"


def report(results: list[dict], startup: Summary, runs: int, help_run: Summary | None = None) -> None:
    print()
    print(f"interpreter start-up (python -c pass): {startup.wall:.3f} s wall, {startup.rss:.1f} MB peak RSS "
          f"(median of {startup.runs})")
    if help_run is not None:
        report_startup(startup, help_run)
    for res in results:
        check: Summary = res["check"]
        parse: Summary = res["parse"]
        floor: Summary = res["floor"]
        big = res["size_mb"] >= 10
        print()
        print(f"== {res['size_mb']} MB model: {res['file']} ({res['file_mb']:.2f} MB), median of {runs} runs ==")
        if not res["clean"]:
            print(f"   WARNING: check did not report a clean model: {' '.join(res['check_output'])}")
        print(f"   {'':24s} {'wall (s)':>9s} {'min-max (s)':>15s} {'peak RSS (MB)':>14s}")
        print(f"   {'lxml parse (baseline)':24s} {parse.wall:9.3f} {parse.wall_min:7.3f}-{parse.wall_max:<7.3f} "
              f"{parse.rss:14.1f}")
        print(f"   {'one pass (floor)':24s} {floor.wall:9.3f} {floor.wall_min:7.3f}-{floor.wall_max:<7.3f} "
              f"{floor.rss:14.1f}")
        print(f"   {'earl-m2t check':24s} {check.wall:9.3f} {check.wall_min:7.3f}-{check.wall_max:<7.3f} "
              f"{check.rss:14.1f}")
        versus: Summary | None = res["versus"]
        if versus is not None:
            print(f"   {'check (--versus)':24s} {versus.wall:9.3f} {versus.wall_min:7.3f}-{versus.wall_max:<7.3f} "
                  f"{versus.rss:14.1f}")
        res["time_ratio"] = check.wall / parse.wall
        res["memory_ratio"] = check.rss / parse.rss
        print(f"   ratio check/parse: time {fmt_ratio(res['time_ratio'], TARGET_TIME_RATIO if big else None)}")
        print(f"                      memory {fmt_ratio(res['memory_ratio'], TARGET_MEMORY_RATIO if big else None)}")
        if versus is not None:
            res["versus_time_ratio"] = versus.wall / parse.wall
            print(f"   ratio check/parse of --versus: time {fmt_ratio(res['versus_time_ratio'], None)}, memory "
                  f"{fmt_ratio(versus.rss / parse.rss, None)}; this checkout / --versus: time "
                  f"{check.wall / versus.wall:.2f}×")
        res["floor_ratio"] = floor.wall / parse.wall
        left = TARGET_TIME_RATIO * parse.wall - floor.wall
        print(f"   ratio floor/parse: time {fmt_ratio(res['floor_ratio'], None)}; at {TARGET_TIME_RATIO:g}× the parse, "
              f"{left:.3f} s would be left beyond the floor for reading, lifting and the rules")
        res["check_floor_ratio"] = check.wall / floor.wall
        print(f"   ratio check/floor: time {fmt_ratio(res['check_floor_ratio'], None)} (check against "
              "the least that any checker in Python over lxml does)")
        if res["size_mb"] == 1:
            ok = "met" if check.wall <= TARGET_SMALL_SECONDS else "NOT met"
            print(f"   check of the 1 MB model: {check.wall:.3f} s  (target ≤ {TARGET_SMALL_SECONDS} s: {ok})")
    by_size = {res["size_mb"]: res for res in results}
    if 10 in by_size and 100 in by_size:
        print()
        print("== growth from 10 MB to 100 MB: (100 MB ratio) / (10 MB ratio) ==")
        for key, label in (("time_ratio", "time"), ("memory_ratio", "memory")):
            growth = by_size[100][key] / by_size[10][key]
            print(f"   {label:7s} {by_size[100][key]:.2f}× / {by_size[10][key]:.2f}× = "
                  f"{fmt_ratio(growth, TARGET_GROWTH)}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="1,10,100", help="model sizes in MB, comma-separated (default 1,10,100)")
    parser.add_argument("--quick", action="store_true", help="only the 1 and 10 MB models")
    parser.add_argument("--runs", type=int, default=5, help="timed runs per command and size (default 5)")
    parser.add_argument("--json", type=Path, metavar="FILE", help="also write the figures as JSON")
    parser.add_argument("--versus", type=Path, metavar="DIR",
                        help="another checkout (set up with make setup) whose check is measured in the same run")
    args = parser.parse_args(argv)
    sizes = [1, 10] if args.quick else [int(s) for s in args.sizes.split(",") if s.strip()]
    check_cmd = earl_m2t_command()
    shown = [os.path.relpath(c, ROOT) if os.path.isabs(c) else c for c in check_cmd]
    print(f"python {sys.version.split()[0]}; check command: {' '.join(shown)} check FILE")
    print(f"measuring start-up ({max(args.runs, STARTUP_RUNS)} runs) ...", flush=True)
    startup, help_run = measure_startup(max(args.runs, STARTUP_RUNS), check_cmd)
    results = []
    for size in sizes:
        print(f"measuring the {size} MB model ({args.runs} runs) ...", flush=True)
        versus_cmd = [str(args.versus.resolve() / ".venv" / "bin" / "earl-m2t")] if args.versus else None
        results.append(measure(size, args.runs, check_cmd, versus_cmd))
    report(results, startup, args.runs, help_run)
    if args.json:
        payload = {"startup": asdict(startup), "help": asdict(help_run), "runs": args.runs,
                   "results": [{**r, "check": asdict(r["check"]), "parse": asdict(r["parse"]),
                                "floor": asdict(r["floor"]), "versus": asdict(r["versus"]) if r["versus"] else None}
                               for r in results]}
        args.json.write_text(json.dumps(payload, indent=2), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

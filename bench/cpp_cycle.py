"""Per-cycle cost of the generated C++ for manip/a.cs against a hand-written loop.

    python bench/cpp_cycle.py                    # 1,000,000 cycles, best of 7
    python bench/cpp_cycle.py --cycles 200000 --repeats 3 --json bench/out/cpp_cycle.json

Generates the pick-and-place sample with ``earl-m2t gen --target cpp`` into
``bench/out/cpp_cycle/gen`` (its ``user/`` folder is deleted first, so the pf bodies are
always the generated stubs, which do nothing), then builds one binary with g++ ``-O2``
from ``bench/cpp/driver.cpp`` (the generated ``manip/a.cs`` subsystem alone, its 14
buffers linked to channels fed by a simple source every cycle) and
``bench/cpp/baseline.cpp`` (the same work written by hand on the same channels), and
runs it. Both are timed in the same process with ``std::chrono::steady_clock``, in two
scenarios (see ``bench/cpp/bench.hpp``): ``hold`` (no command, the tc of ``idle/bb`` is
evaluated and fails every cycle) and ``switching`` (a fresh joint setpoint every cycle:
the tc holds and the guards are evaluated every cycle).

It prints ns per cycle (best repetition, and the median), the cost of the source alone,
the ratio generated/hand-written with and without the source, and the target
(≤ 1.3 × the hand-written loop) next to the figures. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
SOURCES = BENCH / "cpp"
TARGET_RATIO = 1.3
CXXFLAGS = ["-std=c++17", "-O2", "-DNDEBUG", "-Wall", "-Wextra", "-Werror"]


def generate(out: Path) -> None:
    """The sample's C++ project in ``out``, with fresh pf stubs."""
    shutil.rmtree(out / "user", ignore_errors=True)
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(SAMPLE), "--target", "cpp", "-o", str(out)],
                            cwd=ROOT, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"earl-m2t gen failed:\n{result.stdout}{result.stderr}")


def include_flags(gen: Path) -> list[str]:
    return ["-I", str(gen / "runtime"), "-I", str(gen / "generated" / "include"), "-I", str(gen / "user"),
            "-I", str(SOURCES)]


def build(cxx: str, gen: Path, binary: Path) -> float:
    started = time.perf_counter()
    command = [cxx, *CXXFLAGS, *include_flags(gen), str(SOURCES / "driver.cpp"), str(SOURCES / "baseline.cpp"),
               "-o", str(binary)]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"build failed: {' '.join(command)}\n{result.stderr}")
    return time.perf_counter() - started


def run(binary: Path, cycles: int, repeats: int) -> list[dict]:
    result = subprocess.run([str(binary), "--cycles", str(cycles), "--repeats", str(repeats)], capture_output=True,
                            text=True)
    if result.returncode != 0:
        sys.exit(f"{binary.name} failed:\n{result.stderr}")
    return [json.loads(line) for line in result.stdout.splitlines() if line.strip()]


def ratios(row: dict) -> tuple[float, float]:
    """(net, gross): generated / hand-written without and with the source's share."""
    g, b, s = row["generated"]["best"], row["baseline"]["best"], row["source"]["best"]
    net = (g - s) / (b - s) if b > s else float("nan")
    return net, g / b


def report(rows: list[dict], cxx: str) -> None:
    first = rows[0]
    print(f"manip/a.cs (N = 6, generated pf stubs): ns per cycle, best of {first['repeats']} x "
          f"{first['cycles']:,} cycles ({cxx} {' '.join(CXXFLAGS[:3])}); median in brackets")
    header = (f"{'scenario':<10} {'generated':>16} {'hand-written':>16} {'source':>14} "
              f"{'gen - src':>10} {'hand - src':>10} {'ratio':>6} {'gross':>6}  target")
    print(header)
    print("-" * len(header))
    for row in rows:
        g, b, s = row["generated"], row["baseline"], row["source"]
        net, gross = ratios(row)
        verdict = "ok" if net <= TARGET_RATIO else "MISSED"
        print(f"{row['scenario']:<10} {g['best']:>7.1f} ({g['median']:>6.1f}) {b['best']:>7.1f} ({b['median']:>6.1f}) "
              f"{s['best']:>5.1f} ({s['median']:>5.1f}) {g['best'] - s['best']:>10.1f} {b['best'] - s['best']:>10.1f} "
              f"{net:>5.2f}x {gross:>5.2f}x  <= {TARGET_RATIO}x {verdict}")
        if (g["state"], g["iteration"]) != (b["state"], b["iteration"]):
            print(f"  WARNING: the two loops disagree: generated ended in {g['state']} at iteration {g['iteration']}, "
                  f"hand-written in {b['state']} at iteration {b['iteration']}")
    print("ratio = (generated - source) / (hand-written - source): the subsystem's cycle alone; "
          "gross includes the source that feeds the 7 input buffers.")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cycles", type=int, default=1_000_000, help="updateHook() calls per repetition")
    parser.add_argument("--repeats", type=int, default=7, help="repetitions; the best is reported")
    parser.add_argument("--out", type=Path, default=BENCH / "out" / "cpp_cycle", help="work folder")
    parser.add_argument("--cxx", default=os.environ.get("CXX", "g++"), help="C++ compiler (default $CXX or g++)")
    parser.add_argument("--json", type=Path, help="also write the figures to this file")
    args = parser.parse_args(argv)
    if shutil.which(args.cxx) is None:
        sys.exit(f"{args.cxx} not found")
    args.out.mkdir(parents=True, exist_ok=True)
    gen = args.out / "gen"
    generate(gen)
    seconds = build(args.cxx, gen, args.out / "driver")
    print(f"generated {gen.relative_to(ROOT) if gen.is_relative_to(ROOT) else gen}, built in {seconds:.1f} s")
    rows = run(args.out / "driver", args.cycles, args.repeats)
    report(rows, args.cxx)
    if args.json:
        for row in rows:
            row["ratio"], row["ratio_gross"] = ratios(row)
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"target_ratio": TARGET_RATIO, "results": rows}, indent=2) + "\n",
                             encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())

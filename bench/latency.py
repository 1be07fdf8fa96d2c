"""Wake-up latency and idle CPU of the threaded C++ runtime and of the Orocos master.

    python bench/latency.py                       # 10,000 hand-offs per row
    python bench/latency.py --samples 20000 --json bench/out/latency.json

Builds, with g++ -O2, three programs doing the same hand-off (``bench/cpp/latency.hpp``): a
writer thread writes the current time into an input and waits until the reader took it, then
pauses 100..400 us; the reader records, at the start of the iteration the value woke, how long
ago it was written:

* ``earl wake word``: ``bench/cpp/latency_earl.cpp``, an event-driven earl subsystem (its
  obligatory input fed by an ``earl::Channel``) run by ``earl::ThreadedRunner``;
* ``earl polling 100 us``: the same source built with ``-DEARL_WAKE_POLL=1`` (the former
  runner loop, which looks at ready() every 100 us; kept for this comparison only);
* ``std::condition_variable``: ``bench/cpp/latency_cv.cpp``, the hand-off written by hand;
* ``orocos master (generated)``: ``bench/cpp/latency_orocos.cpp`` built with
  ``-DEARL_OROCOS_WAKE=2``, the same subsystem inside an RTT TaskContext doing what the
  generated Orocos master does: its own earl::rtt::WakeActivity
  (``transforms/orocos/runtime/earl/rtt_wake_activity.hpp``), a thread sleeping on an earl wake
  word until data or the subsystem's next deadline, and a dataOnPortHook() that asks it for the
  update step directly; the writer an RTT output port connected to its event port. For
  comparison, the same source built as the masters before: ``orocos fd activity (before)`` (no
  flag: a FileDescriptorActivity whose timeout is the subsystem's next deadline, data going
  through RTT's port queue and a callback step) and ``orocos polling 0.2 ms``
  (``-DEARL_OROCOS_POLL=1``: a plain port, a periodic 0.2 ms activity); and two other paths:
  ``orocos plain Activity`` (``-DEARL_OROCOS_ACTIVITY=1``: RTT's non-periodic Activity, which
  has no timeout) and ``orocos wake act., no hook`` (``-DEARL_OROCOS_WAKE=1``: the wake
  activity with RTT's port queue). Built against the Orocos RTT the tests use
  (``tests/support/orocos.py``; ``OROCOS_RTT_PREFIX`` names another, such as a release build);
  left out, with the reason, when there is none.

Each runs unloaded, then loaded (one spinning process per CPU, started by the bench), in
``--rounds`` rounds: the programs in turn, each time a share of the hand-offs, their samples
merged per program, so that a change of the machine's other load between rows falls on every
program alike. Then,
unloaded, the CPU time (utime + stime from /proc/PID/stat) over a few seconds of:

* the event-driven reader waiting with nothing written (wake word, polling);
* the sample's ``manip/a`` agent executable (its inputs from other agents unconnected: no
  command comes, its event-driven control subsystem waits; its 12 motor and controller
  subsystems stay periodic at 1 ms): with the periodic subsystems sharing a thread per period
  (the default), with a thread each (``--threads subsystem``), and built polling;
* the baseline, ``bench/cpp/timer_loop.cpp``: one thread sleeping to absolute deadlines 1 ms
  apart and doing nothing else, what any 1 kHz loop costs on this machine.

Prints p50, p99 and max latency in microseconds, the ratios p99 wake / p99 condition variable
(target <= 1.5) and p99 wake / p99 polling (target < 1), for the earl runtime and the Orocos
master, idle CPU in % of one core (target < 2 %) and the sample's idle CPU over the 1 kHz
baseline's. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
SOURCES = BENCH / "cpp"
RUNTIME = ROOT / "transforms" / "cpp" / "runtime"
OROCOS_RUNTIME = ROOT / "transforms" / "orocos" / "runtime"  # the RTT side: earl/rtt_wake_activity.hpp
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
CXXFLAGS = ["-std=c++17", "-O2", "-DNDEBUG", "-Wall", "-Wextra", "-Werror", "-pthread"]
POLL = "-DEARL_WAKE_POLL=1"
TARGET_CV = 1.5
TARGET_POLL = 1.0
TARGET_IDLE = 2.0  # % of one core
HOG = "while True:\n    pass\n"
PROGRAMS = {  # name: (source, extra flags)
    "wake": ("latency_earl.cpp", []),
    "poll": ("latency_earl.cpp", [POLL]),
    "cv": ("latency_cv.cpp", []),
}
OROCOS_PROGRAMS = {
    "orocos": ("latency_orocos.cpp", []),
    "orocos_poll": ("latency_orocos.cpp", ["-DEARL_OROCOS_POLL=1"]),
    "orocos_activity": ("latency_orocos.cpp", ["-DEARL_OROCOS_ACTIVITY=1"]),
    "orocos_wake": ("latency_orocos.cpp", ["-DEARL_OROCOS_WAKE=1"]),
    "orocos_wake_hook": ("latency_orocos.cpp", ["-DEARL_OROCOS_WAKE=2"]),
}
# (what, its polling variant): each is compared with the condition variable and its polling
COMPARED = (("wake", "poll"), ("orocos", "orocos_poll"), ("orocos_activity", "orocos_poll"),
            ("orocos_wake", "orocos_poll"), ("orocos_wake_hook", "orocos_poll"))


def build(cxx: str, source: Path, binary: Path, *flags: str) -> None:
    command = [cxx, *CXXFLAGS, str(source), "-o", str(binary), *flags]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"build failed: {' '.join(command)}\n{result.stderr}")


def build_agent(cxx: str, out: Path) -> dict[str, Path]:
    """The sample's manip/a agent executable, with the wake word and with polling."""
    gen = out / "gen"
    shutil.rmtree(gen / "user", ignore_errors=True)
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(SAMPLE), "--target", "cpp", "-o", str(gen)],
                            cwd=ROOT, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"earl-m2t gen failed:\n{result.stdout}{result.stderr}")
    includes = [f"-I{gen / d}" for d in ("runtime", "generated/include", "user")]
    binaries = {}
    for name, flags in (("wake", []), ("poll", [POLL])):
        binaries[name] = out / f"manip_a_{name}"
        build(cxx, gen / "generated" / "src" / "manip_a_main.cpp", binaries[name], *includes, *flags)
    return binaries


def build_orocos(cxx: str, out: Path) -> tuple[dict[str, Path], dict[str, str]]:
    """The Orocos programs, against the RTT of the tests; ({}, why not) when there is none."""
    sys.path.insert(0, str(ROOT))
    from tests.support import orocos  # standard library only

    try:
        rtt = orocos.installation()
    except (orocos.OrocosUnavailable, orocos.OrocosBuildFailed) as error:
        return {}, {"reason": str(error).splitlines()[0]}
    # RTT's own headers as system headers: their deprecation warnings are not this bench's
    flags = [f"-I{RUNTIME}", f"-I{OROCOS_RUNTIME}", f"-I{SOURCES}", "-isystem", str(rtt.prefix / "include"),
             "-DOROCOS_TARGET=gnulinux",
             "-DBOOST_BIND_GLOBAL_PLACEHOLDERS",
             f"-L{rtt.prefix / 'lib'}", "-lorocos-rtt-gnulinux", "-lpthread", "-lrt",
             f"-Wl,-rpath,{rtt.prefix / 'lib'}"]
    binaries = {}
    for name, (source, extra) in OROCOS_PROGRAMS.items():
        binaries[name] = out / f"latency_{name}"
        build(cxx, SOURCES / source, binaries[name], *extra, *flags)
    return binaries, {}


@contextmanager
def cpu_hogs(count: int) -> Iterator[None]:
    hogs = [subprocess.Popen([sys.executable, "-c", HOG], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL) for _ in range(count)]
    try:
        time.sleep(0.5)  # spinning before the first sample
        yield
    finally:
        for hog in hogs:
            hog.kill()
        for hog in hogs:
            hog.wait()


def handoffs(binary: Path, samples: int) -> tuple[dict, list[int]]:
    """One run of ``binary``: its JSON line and its samples in nanoseconds."""
    raw = binary.parent / f"{binary.name}.samples"
    # in the work folder: RTT writes its orocos.log into the current one
    result = subprocess.run([str(binary), "--samples", str(samples)], capture_output=True, text=True, timeout=600,
                            cwd=binary.parent, env={**os.environ, "LATENCY_RAW": str(raw)})
    if result.returncode != 0:
        sys.exit(f"{binary.name} failed:\n{result.stderr}")
    row: dict = json.loads(result.stdout.strip().splitlines()[-1])
    return row, [int(line) for line in raw.read_text().split()]


def merged(row: dict, ns: list[int]) -> dict:
    """``row`` with its percentiles over the samples of every round (as latency.hpp takes them)."""
    ns = sorted(ns)

    def at(q: float) -> float:
        return ns[int(q * (len(ns) - 1))] / 1e3

    return {**row, "samples": len(ns), "p50_us": at(0.5), "p99_us": at(0.99), "max_us": ns[-1] / 1e3}


def rows_of(binaries: dict[str, Path], samples: int, rounds: int, load: str) -> list[dict]:
    """Every program ``rounds`` times in turn, ``samples / rounds`` hand-offs each time, so that
    a change of the machine's other load falls on every program alike; merged per program."""
    first: dict[str, dict] = {}
    ns: dict[str, list[int]] = {name: [] for name in binaries}
    for _ in range(rounds):
        for name, binary in binaries.items():
            row, taken = handoffs(binary, max(1, samples // rounds))
            first.setdefault(name, row)
            ns[name] += taken
    return [{"load": load, "program": name, **merged(first[name], ns[name])} for name in binaries]


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def idle_cpu(command: list[str], window: float) -> float:
    """% of one core the process uses over ``window`` seconds, from 1 s after its start."""
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                               cwd=Path(command[0]).parent)
    try:
        time.sleep(1.0)
        first, started = cpu_seconds(process.pid), time.perf_counter()
        time.sleep(window)
        used, elapsed = cpu_seconds(process.pid) - first, time.perf_counter() - started
    finally:
        _, stderr = process.communicate(timeout=60)
    if process.returncode != 0:
        sys.exit(f"{command[0]} failed:\n{stderr}")
    return 100.0 * used / elapsed


def report(rows: list[dict], idle: list[dict], missing: dict[str, str]) -> None:
    header = f"{'load':<9} {'variant':<28} {'samples':>8} {'p50 us':>9} {'p99 us':>9} {'max us':>10}"
    print(header)
    print("-" * len(header))
    for row in rows:
        print(f"{row['load']:<9} {row['variant']:<28} {row['samples']:>8} {row['p50_us']:>9.2f} {row['p99_us']:>9.2f} "
              f"{row['max_us']:>10.2f}")
    print()
    for load in ("unloaded", "loaded"):
        by = {r["program"]: r for r in rows if r["load"] == load}
        for wake, polling in COMPARED:
            if wake not in by:
                continue
            cv, poll = by[wake]["p99_us"] / by["cv"]["p99_us"], by[wake]["p99_us"] / by[polling]["p99_us"]
            print(f"{load:<9} {by[wake]['variant']:<28} p99 / p99 condition variable = {cv:.2f}  (target <= "
                  f"{TARGET_CV}: {'ok' if cv <= TARGET_CV else 'MISSED'});  p99 / p99 polling = {poll:.2f}  "
                  f"(target < {TARGET_POLL}: {'ok' if poll < TARGET_POLL else 'MISSED'})")
    print()
    print(f"{'idle CPU, unloaded':<62} {'% of one core':>14}")
    floor = next(e["percent"] for e in idle if e.get("baseline"))
    for entry in idle:
        verdict = ""
        if entry.get("target"):
            verdict = f"  target < {TARGET_IDLE} %: {'ok' if entry['percent'] < TARGET_IDLE else 'MISSED'}"
        if entry.get("versus_baseline"):
            verdict += f"  {entry['percent'] / floor:.2f} x baseline" if floor > 0 else "  (baseline 0)"
        print(f"{entry['what']:<62} {entry['percent']:>14.2f}{verdict}")
    if missing:
        print(f"Orocos rows left out: {missing['reason']}")
    print("latency: from the write into the obligatory input to the start of the reader's iteration; "
          "loaded: one spinning process per CPU.")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--samples", type=int, default=10_000, help="hand-offs per row (at least 10,000 advised)")
    parser.add_argument("--rounds", type=int, default=5,
                        help="the programs run in turn this many times per load, their samples merged")
    parser.add_argument("--idle", type=float, default=4.0, help="seconds of each idle CPU measurement")
    parser.add_argument("--out", type=Path, default=BENCH / "out" / "latency", help="work folder")
    parser.add_argument("--cxx", default=os.environ.get("CXX", "g++"), help="C++ compiler (default $CXX or g++)")
    parser.add_argument("--json", type=Path, help="also write the figures to this file")
    args = parser.parse_args(argv)
    if shutil.which(args.cxx) is None:
        sys.exit(f"{args.cxx} not found")
    args.out.mkdir(parents=True, exist_ok=True)
    binaries = {}
    for name, (source, flags) in PROGRAMS.items():
        binaries[name] = args.out / f"latency_{name}"
        build(args.cxx, SOURCES / source, binaries[name], f"-I{RUNTIME}", f"-I{SOURCES}", *flags)
    orocos_binaries, missing = build_orocos(args.cxx, args.out)
    binaries.update(orocos_binaries)
    agent = build_agent(args.cxx, args.out)
    cpus = os.cpu_count() or 2
    print(f"{args.samples:,} hand-offs per row in {args.rounds} rounds (the programs in turn), {cpus} CPU(s); "
          f"{args.cxx} {' '.join(CXXFLAGS[:3])}")
    rows = []
    for load in ("unloaded", "loaded"):
        context = cpu_hogs(cpus) if load == "loaded" else contextmanager(lambda: iter([None]))()
        with context:
            rows += rows_of(binaries, args.samples, args.rounds, load)
    seconds = str(args.idle + 2)
    timer = args.out / "timer_loop"
    build(args.cxx, SOURCES / "timer_loop.cpp", timer)
    runs = [("event-driven reader waiting, nothing written: wake word", [str(binaries["wake"]), "--idle", seconds],
             {"target": True}),
            ("event-driven reader waiting, nothing written: polling", [str(binaries["poll"]), "--idle", seconds], {}),
            ("sample manip/a, a thread per period (default)",
             [str(agent["wake"]), "--threaded", seconds, "--quiet"], {"target": True, "versus_baseline": True}),
            ("sample manip/a, a thread per subsystem",
             [str(agent["wake"]), "--threaded", seconds, "--quiet", "--threads", "subsystem"],
             {"versus_baseline": True}),
            ("sample manip/a, polling build, a thread per subsystem",
             [str(agent["poll"]), "--threaded", seconds, "--quiet", "--threads", "subsystem"],
             {"versus_baseline": True}),
            ("baseline: a bare 1 kHz timer loop (timer_loop.cpp)", [str(timer), seconds], {"baseline": True})]
    if orocos_binaries:
        runs[2:2] = [("Orocos master waiting, nothing written: fd activity (before)",
                      [str(binaries["orocos"]), "--idle", seconds], {}),
                     ("Orocos master waiting, nothing written: generated (wake activity)",
                      [str(binaries["orocos_wake_hook"]), "--idle", seconds], {"target": True}),
                     ("Orocos master waiting, nothing written: polling 0.2 ms",
                      [str(binaries["orocos_poll"]), "--idle", seconds], {})]
    idle = [{"what": what, "percent": idle_cpu(command, args.idle), **flags} for what, command, flags in runs]
    report(rows, idle, missing)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"latency": rows, "idle_cpu_percent": idle}, indent=2) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())

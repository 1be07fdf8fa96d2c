"""The fuzz campaign: seeded mutations of the sample dialects, the corpus, the fixtures and the
FABRIC examples, run through the command line in-process, in worker processes watched by a
per-input bound.

Input ``i`` of seed ``s`` is fully determined by ``(s, i)``: which seed file (or FABRIC
package), which mutations, which command (``COMMANDS``: mostly ``check``; also ``show``,
``convert``, ``gen --force`` for a target, ``diff`` of the input and its seed either way,
``verify --timeout 2``, ``report``; a FABRIC package goes through ``import fabric`` and a check
of what it wrote). Each worker runs its inputs one after the other in one process
(``earl_m2t.cli.app.main``, output captured), under an address-space limit; the parent gives
each command an input runs (a clean check goes on with every target's gen) a bound of the
worker's CPU time (``--bound``, 60 s) and of the time it is blocked (``WALL_FACTOR`` times as
long: neither the worker nor a process it started running or waiting for a CPU, nor its CPU
time growing; tests/fuzz/watch.py), and counts a command that exceeds either as a hang: the
worker is killed and a new one goes on with the next input. A worker starved by a busy machine
(a niced campaign beside other work), or a campaign paused and resumed (``kill -STOP``/``-CONT``
of its process group), is never counted.

An input fails (``tests/fuzz/properties.py``) on an internal error, an exit code outside its
command's table, SPIN refusing the Promela verify wrote, a hang, a peak resident memory over
1 GiB (measured per input: ``tests/fuzz/memory.py``), a convert that exits 0 whose text does not
read back as the same EARL model (``diff`` of source and text), or a check that exits 0 of a
model some target of transforms/targets.toml does not generate. Failing inputs are written to
the regression folder (``tests/fuzz/regressions``), which ``tests/test_fuzz.py`` replays.

    python tests/fuzz/runner.py --inputs 100000 --seed 1 --jobs 2     # what `make fuzz` runs
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import hashlib
import io
import json
import multiprocessing
import os
import random
import resource
import shutil
import sys
import tempfile
import time
import tomllib
from collections import Counter
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.fuzz.memory import peak_kb, reset_peak  # noqa: E402
from tests.fuzz.mutate import mutate  # noqa: E402
from tests.fuzz.mutate_fabric import mutate_package, package_folders, read_package, write_package  # noqa: E402
from tests.fuzz.properties import CLASSES, HANG, INTERNAL, Failure, Run, check_then_gen, contract, memory, round_trip  # noqa: E402
from tests.fuzz.watch import cpu_seconds, runnable  # noqa: E402

CORPUS = ROOT.parent / "shared" / "corpus"
FABRIC = ROOT.parent / "shared" / "fabric" / "examples"
REGRESSIONS = ROOT / "tests" / "fuzz" / "regressions"
MODEL_SUFFIXES = (".uml", ".xmi", ".xml", ".mdzip", ".sysml")
GEN_TARGETS = ("cpp", "msg", "ros", "orocos", "markdown")
# The commands a mutated model is run through, with their shares of the inputs (check takes
# the rest); ``gen`` draws its target from GEN_TARGETS, ``diff`` its direction.
COMMANDS: tuple[tuple[float, tuple[str, ...]], ...] = (
    (0.06, ("show", "--format", "json", "MODEL")),
    (0.07, ("convert", "--to", "sysml", "MODEL", "-o", "OUT/converted.sysml", "--force")),
    (0.07, ("gen",)),
    (0.06, ("diff", "SEED", "MODEL")),
    (0.03, ("verify", "--timeout", "2", "MODEL")),
    (0.015, ("report", "MODEL", "-o", "OUT")),
)
FABRIC_SHARE = 0.04  # of the inputs: a mutated FABRIC package through `import fabric`, then check
# The targets `gen` must write for a model `check` passed: every target of transforms/targets.toml
# but those named here, with why.
CLEAN_GEN_SKIPPED = {"diagrams-png": "renders every diagram with Graphviz: seconds per model"}
ADDRESS_SPACE = 6 << 30  # a worker's limit: a runaway read ends in MemoryError, counted as a failure
DEFAULT_BOUND = 60.0
WALL_FACTOR = 15
# The parent looks at its workers about every second; a longer gap between two looks means the
# parent itself did not run (stopped with its process group, suspended, starved), and nothing
# can be told of the worker over it: at most this much of such a gap counts as blocked.
LONGEST_LOOK_GAP = 5.0
@dataclass(frozen=True)
class Seed:
    path: Path  # a model file, or a FABRIC package's folder
    dialect: str  # what the unmutated file reads as (``sysml-v2``, ``papyrus`` …, ``unreadable``, ``fabric``)


@dataclass(frozen=True)
class Case:
    """One input: the seed it mutates, its bytes (or a FABRIC package's files) and the command
    line run on it, where ``MODEL`` stands for the input, ``SEED`` for its unmutated seed and
    ``OUT`` for an output folder."""

    seed: Seed
    data: bytes
    command: tuple[str, ...]
    package: tuple[tuple[str, bytes], ...] = ()  # a FABRIC package: (path inside it, content)

    @property
    def suffix(self) -> str:
        if self.seed.dialect == "fabric":
            return ""
        name = self.seed.path.name.lower()
        return ".sysml" if name.endswith(".sysml") else ".mdzip" if name.endswith(".mdzip") else \
            Path(name).suffix or ".uml"

    @property
    def size(self) -> int:
        return len(self.data) + sum(len(content) for _, content in self.package)


def seed_files(max_bytes: int | None = None) -> list[Path]:
    """The four sample dialects, the fixtures and the corpus (when beside the checkout), sorted."""
    folders = [ROOT / "samples", ROOT / "tests" / "fixtures", CORPUS]
    found: list[Path] = []
    for folder in folders:
        if folder.is_dir():
            found.extend(p for p in folder.rglob("*") if p.is_file() and p.name.lower().endswith(MODEL_SUFFIXES)
                         and "regressions" not in p.parts)
    return sorted((p for p in found if max_bytes is None or p.stat().st_size <= max_bytes), key=str)


def seed_dialect(path: Path) -> str:
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.read.xmi_index import read_raw_model

    if path.name.lower().endswith(".sysml"):
        return "sysml-v2"
    try:
        return read_raw_model(path).dialect or "unknown"
    except ModelReadError:
        return "unreadable"


def seeds(max_bytes: int | None = None) -> list[Seed]:
    return [Seed(path, seed_dialect(path)) for path in seed_files(max_bytes)]


def fabric_seeds() -> list[Seed]:
    """The FABRIC packages of ``../shared/fabric/examples`` (when beside the checkout)."""
    return [Seed(folder, "fabric") for folder in package_folders(FABRIC)]


def make_case(seed_number: int, index: int, pool: list[Seed], packages: list[Seed] | None = None) -> Case:
    """Input ``index`` of seed ``seed_number``: always the same seed file, mutations and command."""
    rng = random.Random(f"earl-m2t-fuzz/{seed_number}/{index}")
    if packages and rng.random() < FABRIC_SHARE:
        seed = rng.choice(packages)
        package = mutate_package(read_package(seed.path), rng)
        return Case(seed, b"", ("import", "fabric", "MODEL", "-o", "OUT/imported.sysml", "--force"),
                    tuple(sorted(package.items())))
    seed = rng.choices(pool, weights=[_weight(s.path) for s in pool])[0]
    data = mutate(seed.path.read_bytes(), _suffix(seed.path), rng)
    roll = rng.random()
    command: tuple[str, ...] = ("check", "MODEL")
    for share, line in COMMANDS:
        if roll < share:
            command = line
            break
        roll -= share
    if command[0] == "gen":
        command = ("gen", "--force", "--target", rng.choice(GEN_TARGETS), "MODEL", "-o", "OUT")
    elif command[0] == "diff" and rng.random() < 0.5:
        command = ("diff", "MODEL", "SEED")
    return Case(seed, data, command)


@functools.cache
def _weight(path: Path) -> float:
    """How often a seed is drawn: files above 20 kB (SysML v2 text above 4 kB, whose parser is the
    slowest stage) less often, in proportion but at least a tenth as often, so that large models do
    not take the whole campaign."""
    size = max(path.stat().st_size, 1)
    return min(1.0, max(0.1, (4_000 if _suffix(path) == ".sysml" else 20_000) / size))


def _suffix(path: Path) -> str:
    name = path.name.lower()
    return ".sysml" if name.endswith(".sysml") else ".mdzip" if name.endswith(".mdzip") else path.suffix.lower()


def prepare_folder(folder: Path) -> None:
    """What hostile hrefs name beside an input: a FIFO, a link to /dev/zero, a link to itself."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, make in (("pipe.uml", lambda p: os.mkfifo(p)), ("zero.uml", lambda p: os.symlink("/dev/zero", p)),
                       ("loop.uml", lambda p: os.symlink("loop.uml", p))):
        path = folder / name
        if not os.path.lexists(path):
            make(path)


@functools.cache
def _targets() -> dict[str, dict]:
    with open(ROOT / "transforms" / "targets.toml", "rb") as stream:
        return tomllib.load(stream)


def clean_gen_targets() -> tuple[str, ...]:
    """The targets of transforms/targets.toml that a model ``check`` passed must generate."""
    return tuple(name for name in _targets() if name not in CLEAN_GEN_SKIPPED)


def static_only_targets() -> frozenset[str]:
    """The targets that declare they do not run a variable structure (``variable_structure = false``)."""
    return frozenset(name for name, spec in _targets().items() if spec.get("variable_structure") is False)


# In a worker: how many commands it has started, which the parent reads to bound each command
# (not the several commands of one input together) by ``--bound``.
_commands_started: Any = None


def invoke(argv: list[str]) -> Run:
    """One command line in this process, its output captured."""
    from earl_m2t.cli.app import main

    if _commands_started is not None:
        _commands_started.value += 1

    stdout, stderr = io.StringIO(), io.StringIO()
    code: int | None
    try:
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = main(argv)
    except SystemExit as exit_:
        code = exit_.code if isinstance(exit_.code, int) else 2
    except BaseException as exc:  # escaped main: a failure like an internal error
        return Run(tuple(argv), None, f"escaped main: {type(exc).__name__}: {str(exc)[:300]}")
    return Run(tuple(argv), code, stdout.getvalue()[-20_000:] + "\n" + stderr.getvalue()[-20_000:])


@dataclass(frozen=True)
class Outcome:
    """What an input came to: the exit code of its command, every failure of its runs, its
    peak resident memory."""

    code: int
    failures: tuple[Failure, ...]
    peak_kb: int


def _argv(template: tuple[str, ...], model: Path, seed: Path, out: Path) -> list[str]:
    places = {"MODEL": str(model), "SEED": str(seed), "OUT": str(out)}
    return [places.get(word, word) if not word.startswith("OUT/") else str(out / word[4:]) for word in template]


def run_case(case: Case, folder: Path) -> Outcome:
    """Run one input in this process with the properties that follow from its command: a
    convert that exits 0 reads back as its source, a check that exits 0 lets every target
    generate, and the whole stays under the memory bound."""
    if case.package:
        model = folder / "package"
        shutil.rmtree(model, ignore_errors=True)
        write_package(dict(case.package), model)
    else:
        model = folder / f"input{case.suffix}"
        model.write_bytes(case.data)
    out = folder / "out"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir()
    measured = reset_peak()
    first = invoke(_argv(case.command, model, case.seed.path, out))
    runs = [first]
    found: list[Failure] = []
    checked: Path | None = model if first.command == "check" and first.code == 0 else None
    if first.command == "convert" and first.code == 0:
        diff = invoke(["diff", str(model), str(out / "converted.sysml")])
        runs.append(diff)
        found.extend(filter(None, [round_trip(diff)]))
    if first.command == "import" and first.code == 0:
        check = invoke(["check", str(out / "imported.sysml")])
        runs.append(check)
        checked = out / "imported.sysml" if check.code == 0 else None
    if checked is not None:
        gens = [invoke(["gen", "--target", target, str(checked), "-o", str(out / "gen" / target)])
                for target in clean_gen_targets()]
        runs.extend(gens)
        found.extend(filter(None, [check_then_gen(gens, static_only_targets())]))
    found.extend(failure for run in runs if (failure := contract(run)))
    if measured:
        found.extend(filter(None, [memory(peak_kb(), case.size)]))
    code = first.code if first.code is not None else -3
    return Outcome(code, tuple(found), peak_kb() if measured else 0)


def _worker(connection: Connection, seed_number: int, pool: list[Seed], packages: list[Seed], folder: str,
            commands_started: Any) -> None:
    global _commands_started
    _commands_started = commands_started
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    os.environ.pop("EARL_M2T_CACHE", None)
    place = Path(folder)
    prepare_folder(place)
    while True:
        index = connection.recv()
        if index is None:
            return
        try:
            case = make_case(seed_number, index, pool, packages)
        except Exception as exc:  # a defect of the mutator, not of earl-m2t: reported, not counted
            connection.send((index, -2, (), 0, "mutator", "-"))
            print(f"the mutator failed on input {index}: {type(exc).__name__}: {exc}"[:400], file=sys.stderr)
            continue
        outcome = run_case(case, place)
        connection.send((index, outcome.code, tuple((f.kind, f.message) for f in outcome.failures), outcome.peak_kb,
                         case.seed.dialect, case.command[0]))


@dataclass
class Result:
    index: int
    dialect: str
    command: str
    code: int  # the command's exit code; -1 a hang, -2 the mutator failed, -3 an exception escaped main
    failures: tuple[tuple[str, str], ...] = ()  # (class, message) of each failure of the input's runs
    peak_kb: int = 0

    @property
    def message(self) -> str:
        return "; ".join(f"{kind}: {message}" for kind, message in self.failures)


class _Slot:
    """A worker, the input it runs, and how long the command it runs has been blocked so far."""

    def __init__(self, process: multiprocessing.process.BaseProcess, connection: Connection, index: int,
                 cpu_since: float = 0.0, commands_started: Any = None) -> None:
        self.process = process
        self.connection = connection
        self.index = index
        self.cpu_since = cpu_since  # the worker's CPU time when its current command began
        self.blocked = 0.0  # seconds in which neither it ran nor waited for a CPU
        self.commands_started = commands_started  # the worker's count (a shared value), or None
        self._commands = commands_started.value if commands_started is not None else 0
        self._cpu = cpu_since
        self._looked = time.monotonic()

    def watch(self) -> float:
        """The worker's CPU time now; the time since the last look (at most LONGEST_LOOK_GAP)
        counts as blocked unless the worker used the CPU meanwhile or it (or a process it
        started) is runnable now. A command started since the last look begins the count anew:
        the bound is per command, and an input may run ten (a clean check, then every gen)."""
        cpu = cpu_seconds(self.process.pid or 0)
        now = time.monotonic()
        if self.commands_started is not None and self.commands_started.value != self._commands:
            self._commands = self.commands_started.value
            self.cpu_since, self.blocked = self._cpu, 0.0
        if cpu == self._cpu and not runnable(self.process.pid or 0):
            self.blocked += min(now - self._looked, LONGEST_LOOK_GAP)
        self._cpu, self._looked = cpu, now
        return cpu


class Campaign:
    """Inputs ``first`` … ``first + count - 1`` of a seed, over ``jobs`` watched workers."""

    def __init__(self, seed_number: int, pool: list[Seed], bound: float = DEFAULT_BOUND, jobs: int = 1,
                 packages: list[Seed] | None = None) -> None:
        self.seed_number = seed_number
        self.pool = pool
        self.packages = fabric_seeds() if packages is None else packages
        self.bound = bound
        self.jobs = max(jobs, 1)
        self._context = multiprocessing.get_context("fork")

    def run(self, first: int, count: int, progress: bool = False, regressions: Path | None = None) -> list[Result]:
        """Run the inputs; with ``progress``, a summary so far every 5,000 inputs on stderr; with
        ``regressions``, each failing input is saved there as soon as it is found."""
        pending = list(range(first + count - 1, first - 1, -1))
        results: list[Result] = []
        scratch = Path(tempfile.mkdtemp(prefix="earl-m2t-fuzz-"))
        workers: dict[int, _Slot] = {}
        started = time.monotonic()
        saved = reported = 0
        try:
            slot_numbers = iter(range(1 << 30))
            while pending or workers:
                while pending and len(workers) < self.jobs:
                    slot = next(slot_numbers)
                    parent, child = self._context.Pipe()
                    commands_started = self._context.RawValue("Q", 0)
                    arguments = (child, self.seed_number, self.pool, self.packages, str(scratch / f"w{slot}"),
                                 commands_started)
                    process: multiprocessing.process.BaseProcess = self._context.Process(
                        target=_worker, args=arguments, daemon=True)
                    process.start()
                    child.close()
                    index = pending.pop()
                    parent.send(index)
                    workers[slot] = _Slot(process, parent, index, 0.0, commands_started)
                ready = multiprocessing.connection.wait([w.connection for w in workers.values()], timeout=1.0)
                for slot, worker in list(workers.items()):
                    process, connection = worker.process, worker.connection
                    if connection in ready:
                        try:
                            done, code, found, peak, dialect, command = connection.recv()
                        except (EOFError, OSError):  # the worker died (a crash in C code, a kill)
                            process.join()
                            results.append(self._result(worker.index, -3, INTERNAL,
                                                        f"worker died (exit {process.exitcode})"))
                            del workers[slot]
                            continue
                        results.append(Result(done, dialect, command, code, found, peak))
                        if pending:
                            index = pending.pop()
                            connection.send(index)
                            workers[slot] = _Slot(process, connection, index, cpu_seconds(process.pid or 0),
                                                  worker.commands_started)
                        else:
                            connection.send(None)
                            process.join()
                            del workers[slot]
                    elif (worker.watch() - worker.cpu_since > self.bound
                          or worker.blocked > self.bound * WALL_FACTOR):
                        process.kill()
                        process.join()
                        results.append(self._result(worker.index, -1, HANG,
                                                    f"a command without a result within {self.bound:g} s of "
                                                    f"CPU time or {self.bound * WALL_FACTOR:g} s blocked"))
                        del workers[slot]
                while saved < len(results):
                    if regressions is not None and results[saved].failures:
                        found = self.save(results[saved], regressions)
                        print(f"input {results[saved].index} ({results[saved].command}): {results[saved].message} "
                              f"-> {found}", file=sys.stderr, flush=True)
                    saved += 1
                if progress and len(results) >= reported + 5000:
                    reported = len(results) - len(results) % 5000
                    rate = len(results) / max(time.monotonic() - started, 1e-9)
                    print(f"{len(results)} inputs, {rate:.1f}/s; so far:\n{summary(results)}", file=sys.stderr,
                          flush=True)
        finally:
            for worker in workers.values():
                worker.process.kill()
                worker.process.join()
            shutil.rmtree(scratch, ignore_errors=True)
        return sorted(results, key=lambda r: r.index)

    def _result(self, index: int, code: int, kind: str, message: str) -> Result:
        case = self.case(index)
        return Result(index, case.seed.dialect, case.command[0], code, ((kind, message),))

    def case(self, index: int) -> Case:
        return make_case(self.seed_number, index, self.pool, self.packages)

    def save(self, result: Result, folder: Path = REGRESSIONS) -> Path:
        """A failing input as a regression: the file (a FABRIC package: its folder), and beside it
        what was run and what happened; for a diff against the seed, the seed too (``NAME.seed.SUFFIX``)."""
        case = self.case(result.index)
        digest = hashlib.sha256(case.data + repr(case.package).encode()).hexdigest()[:12]
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{result.dialect}-{digest}{case.suffix}"
        if case.package:
            shutil.rmtree(path, ignore_errors=True)
            write_package(dict(case.package), path)
        else:
            path.write_bytes(case.data)
        if "SEED" in case.command:
            path.with_name(path.name + ".seed" + case.suffix).write_bytes(case.seed.path.read_bytes())
        origin = case.seed.path
        shown = origin.relative_to(ROOT) if origin.is_relative_to(ROOT) else \
            origin.relative_to(ROOT.parent) if origin.is_relative_to(ROOT.parent) else Path(origin.name)
        note = {"command": list(case.command), "seed": self.seed_number, "input": result.index,
                "from": shown.as_posix(), "classes": sorted({kind for kind, _ in result.failures}),
                "found": result.message, "exit": result.code, "peak_kb": result.peak_kb}
        path.with_name(path.name + ".json").write_text(json.dumps(note, indent=2, ensure_ascii=False) + "\n",
                                                        encoding="utf-8")
        return path


def failures(results: list[Result]) -> list[Result]:
    return [r for r in results if r.failures]


_CODES = {0: "exit 0", 1: "exit 1", 2: "exit 2", 3: "exit 3", -1: "hang", -3: "died"}


def summary(results: list[Result]) -> str:
    """Counts per command and exit code, inputs per seed dialect, failures per class: the
    campaign's closing note."""
    by_command: dict[str, Counter[int]] = {}
    for result in results:
        by_command.setdefault(result.command, Counter())[result.code] += 1
    codes = sorted({c for counts in by_command.values() for c in counts} | {0, 1, 2, 3, -1},
                   key=lambda c: (c < 0, abs(c)))
    lines = [f"{'command':<12}{'inputs':>8}" + "".join(f"{_CODES.get(c, f'exit {c}'):>9}" for c in codes)]
    total: Counter[int] = Counter()
    for command in sorted(by_command):
        counts = by_command[command]
        total.update(counts)
        lines.append(f"{command:<12}{sum(counts.values()):>8}" + "".join(f"{counts[c]:>9}" for c in codes))
    lines.append(f"{'total':<12}{sum(total.values()):>8}" + "".join(f"{total[c]:>9}" for c in codes))
    dialects = Counter(r.dialect for r in results)
    lines.append("seed dialects: " + ", ".join(f"{name} {count}" for name, count in sorted(dialects.items())))
    classes = Counter(kind for r in results for kind in {k for k, _ in r.failures})
    lines.append("failures: " + ", ".join(f"{kind} {classes[kind]}" for kind in CLASSES) +
                 f" ({len(failures(results))} input(s))")
    peaks = [r.peak_kb for r in results if r.peak_kb]
    if peaks:
        lines.append(f"peak resident memory: largest {max(peaks) / 1024:.0f} MiB of {len(peaks)} measured input(s)")
    broken = [r for r in results if r.code == -2]  # the mutator's own defects, never expected
    if broken:
        lines.append(f"the mutator failed on {len(broken)} input(s), first {broken[0].index}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--inputs", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--first", type=int, default=0, help="the number of the first input")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--bound", type=float, default=DEFAULT_BOUND,
                        help="seconds of CPU time an input may take before it is a hang")
    parser.add_argument("--regressions", type=Path, default=REGRESSIONS, help="where failing inputs are written")
    args = parser.parse_args(argv)
    pool = seeds()
    print(f"fuzz: seed {args.seed}, inputs {args.first}..{args.first + args.inputs - 1}, {len(pool)} seed files, "
          f"{args.jobs} worker(s), bound {args.bound:g} s", file=sys.stderr, flush=True)
    campaign = Campaign(args.seed, pool, args.bound, args.jobs)
    results = campaign.run(args.first, args.inputs, progress=True, regressions=args.regressions)
    bad = failures(results)
    print(summary(results))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

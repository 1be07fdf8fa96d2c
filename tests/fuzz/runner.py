"""The fuzz campaign: seeded mutations of the sample dialects, the corpus and the fixtures, run
through the command line in-process, in worker processes watched by a per-input bound.

Input ``i`` of seed ``s`` is fully determined by ``(s, i)``: which seed file, which mutations,
which command (mostly ``check``; also ``show``, ``convert`` and ``gen --force`` for a target).
Each worker runs its inputs one after the other in one process (``earl_m2t.cli.app.main``, output
captured), under an address-space limit; the parent gives every input a generous bound of the
worker's CPU time (``--bound``, 60 s; a worker starved by a busy machine is not counted) and of
wall time (``WALL_FACTOR`` times as long: an input blocked without using the CPU), and counts an
input that exceeds either as a hang: the worker is killed and a new one goes on with the next
input. An input counts as a failure when the command ends in an internal error (exit 3, or an
exception escaping ``main``), in an exit code other than 0, 1 or 2, or in a hang; failing inputs
are written to the regression folder (``tests/fuzz/regressions``), which ``tests/test_fuzz.py``
replays.

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
from collections import Counter
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.fuzz.mutate import mutate  # noqa: E402

CORPUS = ROOT.parent / "shared" / "corpus"
REGRESSIONS = ROOT / "tests" / "fuzz" / "regressions"
MODEL_SUFFIXES = (".uml", ".xmi", ".xml", ".mdzip", ".sysml")
GEN_TARGETS = ("cpp", "msg", "ros", "orocos", "markdown")
ADDRESS_SPACE = 6 << 30  # a worker's limit: a runaway read ends in MemoryError, counted as a failure
DEFAULT_BOUND = 60.0
WALL_FACTOR = 15
_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid: int) -> float:
    """User and system CPU time of a running process (0 when it cannot be read)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as stream:
            fields = stream.read().rsplit(b")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / _TICKS
    except (OSError, IndexError, ValueError):
        return 0.0


@dataclass(frozen=True)
class Seed:
    path: Path
    dialect: str  # what the unmutated file reads as (``sysml-v2``, ``papyrus`` …, ``unreadable``)


@dataclass(frozen=True)
class Case:
    """One input: the seed it mutates, its bytes and the command run on it."""

    seed: Seed
    data: bytes
    command: tuple[str, ...]  # the arguments before the model path; the model path is last but for gen

    @property
    def suffix(self) -> str:
        name = self.seed.path.name.lower()
        return ".sysml" if name.endswith(".sysml") else ".mdzip" if name.endswith(".mdzip") else \
            Path(name).suffix or ".uml"


def seed_files(max_bytes: int | None = None) -> list[Path]:
    """The four sample dialects, the fixtures and the corpus (when beside the checkout), sorted."""
    folders = [ROOT / "samples", ROOT / "tests" / "fixtures", CORPUS]
    found = []
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


def make_case(seed_number: int, index: int, pool: list[Seed]) -> Case:
    rng = random.Random(f"earl-m2t-fuzz/{seed_number}/{index}")
    seed = rng.choices(pool, weights=[_weight(s.path) for s in pool])[0]
    data = mutate(seed.path.read_bytes(), _suffix(seed.path), rng)
    roll = rng.random()
    if roll < 0.80:
        command: tuple[str, ...] = ("check",)
    elif roll < 0.86:
        command = ("show", "--format", "json")
    elif roll < 0.90:
        command = ("convert", "--to", "sysml")
    else:
        command = ("gen", "--force", "--target", rng.choice(GEN_TARGETS))
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


def run_case(case: Case, folder: Path) -> tuple[int, str]:
    """Run one input in this process: (exit code, the first line of stderr when it failed)."""
    from earl_m2t.cli.app import main

    model = folder / f"input{case.suffix}"
    model.write_bytes(case.data)
    out = folder / "out"
    if out.exists():
        shutil.rmtree(out)
    argv = list(case.command)
    if argv[0] == "gen":
        argv += [str(model), "-o", str(out)]
    elif argv[0] == "convert":
        argv += [str(model), "-o", str(folder / "converted.sysml"), "--force"]
    else:
        argv.append(str(model))
    stdout, stderr = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = main(argv)
    except SystemExit as exit_:
        code = exit_.code if isinstance(exit_.code, int) else 2
    except BaseException as exc:  # escaped main: a failure like an internal error
        return 3, f"escaped main: {type(exc).__name__}: {str(exc)[:300]}"
    text = stderr.getvalue()
    internal = next((line for line in text.splitlines() if "internal error" in line), "")
    if code not in (0, 1, 2) or internal:
        first = internal or next(iter(text.strip().splitlines()), "")
        return (code if code not in (0, 1, 2) else 3), first[:400]
    return code, ""


def _worker(connection: Connection, seed_number: int, pool: list[Seed], folder: str) -> None:
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    os.environ.pop("EARL_M2T_CACHE", None)
    place = Path(folder)
    prepare_folder(place)
    while True:
        index = connection.recv()
        if index is None:
            return
        try:
            case = make_case(seed_number, index, pool)
        except Exception as exc:  # a defect of the mutator, not of earl-m2t: reported, not counted
            connection.send((index, -2, f"the mutator failed: {type(exc).__name__}: {exc}"[:400], "mutator", "-"))
            continue
        code, message = run_case(case, place)
        connection.send((index, code, message, case.seed.dialect, case.command[0]))


@dataclass
class Result:
    index: int
    dialect: str
    command: str
    code: int  # 0, 1, 2; 3 an internal error; -1 a hang
    message: str


class Campaign:
    """Inputs ``first`` … ``first + count - 1`` of a seed, over ``jobs`` watched workers."""

    def __init__(self, seed_number: int, pool: list[Seed], bound: float = DEFAULT_BOUND, jobs: int = 1) -> None:
        self.seed_number = seed_number
        self.pool = pool
        self.bound = bound
        self.jobs = max(jobs, 1)
        self._context = multiprocessing.get_context("fork")

    def run(self, first: int, count: int, progress: bool = False, regressions: Path | None = None) -> list[Result]:
        """Run the inputs; with ``progress``, a summary so far every 5,000 inputs on stderr; with
        ``regressions``, each failing input is saved there as soon as it is found."""
        pending = list(range(first + count - 1, first - 1, -1))
        results: list[Result] = []
        scratch = Path(tempfile.mkdtemp(prefix="earl-m2t-fuzz-"))
        # slot -> (worker, its connection, the input it runs, wall clock and worker CPU time when it began)
        workers: dict[int, tuple[multiprocessing.process.BaseProcess, Connection, int, float, float]] = {}
        started = time.monotonic()
        saved = reported = 0
        try:
            slot_numbers = iter(range(1 << 30))
            while pending or workers:
                while pending and len(workers) < self.jobs:
                    slot = next(slot_numbers)
                    parent, child = self._context.Pipe()
                    process = self._context.Process(target=_worker, args=(child, self.seed_number, self.pool,
                                                                          str(scratch / f"w{slot}")), daemon=True)
                    process.start()
                    child.close()
                    index = pending.pop()
                    parent.send(index)
                    workers[slot] = (process, parent, index, time.monotonic(), 0.0)
                ready = multiprocessing.connection.wait([w[1] for w in workers.values()], timeout=1.0)
                for slot, (process, connection, index, since, cpu_since) in list(workers.items()):
                    if connection in ready:
                        try:
                            done, code, message, dialect, command = connection.recv()
                        except (EOFError, OSError):  # the worker died (a crash in C code, a kill)
                            process.join()
                            results.append(self._result(index, 3, f"worker died (exit {process.exitcode})"))
                            del workers[slot]
                            continue
                        results.append(Result(done, dialect, command, code, message))
                        if pending:
                            index = pending.pop()
                            connection.send(index)
                            workers[slot] = (process, connection, index, time.monotonic(),
                                             cpu_seconds(process.pid or 0))
                        else:
                            connection.send(None)
                            process.join()
                            del workers[slot]
                    elif (cpu_seconds(process.pid or 0) - cpu_since > self.bound
                          or time.monotonic() - since > self.bound * WALL_FACTOR):
                        process.kill()
                        process.join()
                        results.append(self._result(index, -1, f"no result within {self.bound:g} s of CPU time "
                                                               f"or {self.bound * WALL_FACTOR:g} s: a hang"))
                        del workers[slot]
                while saved < len(results):
                    if regressions is not None and results[saved].code in (3, -1):
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
            for process, _, _, _, _ in workers.values():
                process.kill()
                process.join()
            shutil.rmtree(scratch, ignore_errors=True)
        return sorted(results, key=lambda r: r.index)

    def _result(self, index: int, code: int, message: str) -> Result:
        case = make_case(self.seed_number, index, self.pool)
        return Result(index, case.seed.dialect, case.command[0], code, message)

    def save(self, result: Result, folder: Path = REGRESSIONS) -> Path:
        """A failing input as a regression: the file, and beside it what was run and what happened."""
        case = make_case(self.seed_number, result.index, self.pool)
        digest = hashlib.sha256(case.data).hexdigest()[:12]
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / f"{result.dialect}-{digest}{case.suffix}"
        path.write_bytes(case.data)
        origin = case.seed.path
        shown = origin.relative_to(ROOT) if origin.is_relative_to(ROOT) else \
            origin.relative_to(CORPUS.parent.parent) if origin.is_relative_to(CORPUS) else Path(origin.name)
        note = {"command": list(case.command), "seed": self.seed_number, "input": result.index,
                "from": shown.as_posix(), "found": result.message, "exit": result.code}
        path.with_name(path.name + ".json").write_text(json.dumps(note, indent=2, ensure_ascii=False) + "\n",
                                                        encoding="utf-8")
        return path


def failures(results: list[Result]) -> list[Result]:
    return [r for r in results if r.code not in (0, 1, 2)]


def summary(results: list[Result]) -> str:
    """Counts per seed dialect and exit code, then per command: the campaign's closing note."""
    by_dialect: dict[str, Counter[int]] = {}
    for result in results:
        by_dialect.setdefault(result.dialect, Counter())[result.code] += 1
    names = {0: "exit 0", 1: "exit 1", 2: "exit 2", 3: "internal", -1: "hang"}
    broken = [r for r in results if r.code == -2]  # the mutator's own defects, never expected
    lines = [f"{'dialect':<22}{'inputs':>8}" + "".join(f"{names[c]:>10}" for c in (0, 1, 2, 3, -1))]
    total: Counter[int] = Counter()
    for dialect in sorted(by_dialect):
        counts = by_dialect[dialect]
        total.update(counts)
        lines.append(f"{dialect:<22}{sum(counts.values()):>8}" + "".join(f"{counts[c]:>10}" for c in (0, 1, 2, 3, -1)))
    lines.append(f"{'total':<22}{sum(total.values()):>8}" + "".join(f"{total[c]:>10}" for c in (0, 1, 2, 3, -1)))
    if broken:
        lines.append(f"the mutator failed on {len(broken)} input(s), first {broken[0].index}: {broken[0].message}")
    commands = Counter(r.command for r in results)
    lines.append("commands: " + ", ".join(f"{name} {count}" for name, count in sorted(commands.items())))
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

"""What the campaign holds every run to, as data and small checks on a run's result.

``EXIT_CODES`` is each command's contract (its module in ``earl_m2t/cli/`` and
docs/untrusted-models.md): 0 clean, 1 findings (or differences, or diagrams that cannot be
made), 2 unreadable input; ``verify`` also 3, not proven (a depth or time bound stopped SPIN).
The checks take a finished run (``Run``) and return the ``Failure`` it is, or ``None``; they are
pure, so that a test can feed them a made-up run and see each one fail."""

from __future__ import annotations

import re
from dataclasses import dataclass

EXIT_CODES: dict[str, frozenset[int]] = {
    "check": frozenset({0, 1, 2}),
    "show": frozenset({0, 1, 2}),
    "convert": frozenset({0, 1, 2}),
    "gen": frozenset({0, 1, 2}),
    "diff": frozenset({0, 1, 2}),
    "report": frozenset({0, 1, 2}),
    "import": frozenset({0, 1, 2}),  # import fabric
    "verify": frozenset({0, 1, 2, 3}),
}

# the failure classes, in the order the summary lists them
INTERNAL, BAD_EXIT, HANG, MEMORY, ROUND_TRIP, CHECK_GEN, SPIN = (
    "internal error", "bad exit code", "hang", "memory", "round-trip difference", "check-clean-gen-fails",
    "spin-rejected")
CLASSES = (INTERNAL, BAD_EXIT, HANG, MEMORY, ROUND_TRIP, CHECK_GEN, SPIN)

# the peak resident memory a run may reach, for an input under MEMORY_INPUT_LIMIT bytes
# (docs/untrusted-models.md): the worker's own modules and data included
MEMORY_BOUND_KB = 1 << 20  # 1 GiB
MEMORY_INPUT_LIMIT = 10 << 20
_INTERNAL = re.compile(r"internal error|Traceback \(most recent call last\)")
_SPIN_REJECTED = re.compile(r"spin -a failed|\bcc failed")


@dataclass(frozen=True)
class Run:
    """One command line run: its arguments, its exit code (``None``: an exception escaped
    ``main``) and what it printed, stdout and stderr together."""

    argv: tuple[str, ...]
    code: int | None
    output: str

    @property
    def command(self) -> str:
        return self.argv[0] if self.argv else ""


@dataclass(frozen=True)
class Failure:
    kind: str  # one of CLASSES
    message: str  # one line


def _line(run: Run, pattern: re.Pattern[str] | None = None) -> str:
    lines = run.output.strip().splitlines()
    found = next((line for line in lines if pattern.search(line)), "") if pattern else ""
    return (found or next(iter(lines), "")).strip()[:400]


def contract(run: Run) -> Failure | None:
    """An internal error (or an exception escaping ``main``), SPIN refusing the Promela that
    verify wrote, or an exit code outside the command's table."""
    if run.code is None or _INTERNAL.search(run.output):
        return Failure(INTERNAL, _line(run, _INTERNAL))
    if run.command == "verify" and _SPIN_REJECTED.search(run.output):
        return Failure(SPIN, _line(run, _SPIN_REJECTED))
    if run.code not in EXIT_CODES.get(run.command, frozenset()):
        return Failure(BAD_EXIT, f"exit {run.code}: {_line(run)}")
    return None


def round_trip(diff: Run) -> Failure | None:
    """``diff SOURCE CONVERTED`` after a convert that exited 0: anything but 0 (no EARL change)."""
    if diff.code == 0:
        return None
    return Failure(ROUND_TRIP, f"diff of the source and what convert wrote: exit {diff.code}: {_line(diff)}")


# What a target that declares ``variable_structure = false`` in transforms/targets.toml says when
# it refuses a model with configurations: a documented limit of that target, not a miss of check
REFUSES_CONFIGURATIONS = "does not switch configurations yet"


def check_then_gen(gens: list[Run], static_only: frozenset[str] = frozenset()) -> Failure | None:
    """The gen runs of a model that ``check`` passed: each must exit 0, but a target of
    ``static_only`` may refuse a model with configurations (its declared limit)."""
    for run in gens:
        if run.code != 0:
            target = run.argv[run.argv.index("--target") + 1] if "--target" in run.argv else "?"
            if target in static_only and run.code == 1 and REFUSES_CONFIGURATIONS in run.output:
                continue
            return Failure(CHECK_GEN, f"check exits 0, gen --target {target} exits {run.code}: {_line(run)}")
    return None


def memory(peak_kb: int, input_bytes: int, bound_kb: int = MEMORY_BOUND_KB) -> Failure | None:
    """The peak resident memory of an input's runs, for an input under the size the bound is for."""
    if input_bytes >= MEMORY_INPUT_LIMIT or peak_kb <= bound_kb:
        return None
    return Failure(MEMORY, f"peak resident memory {peak_kb / 1024:.0f} MiB, "
                           f"over the bound of {bound_kb / 1024:.0f} MiB")

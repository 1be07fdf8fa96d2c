"""Replay a saved failing input (``tests/fuzz/regressions/NAME`` and its note ``NAME.json``) with
every property the campaign holds it to, not only the exit code of its command: a check that
exits 0 still runs every target's gen, a convert still reads back, an import still checks.

    python tests/fuzz/replay.py tests/fuzz/regressions/papyrus-935206a7d2ed.uml

Prints each failure on a line and exits 1 when there is one, 0 when the input now holds.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.fuzz.mutate_fabric import read_package  # noqa: E402
from tests.fuzz.runner import Case, Outcome, Seed, prepare_folder, run_case  # noqa: E402

# An older note names no MODEL: the model went last, then the output of gen and convert.
_OLD_OUTPUT = {"gen": ("-o", "OUT"), "convert": ("-o", "OUT/converted.sysml")}


def note_of(model: Path) -> dict[str, object]:
    note: dict[str, object] = json.loads(model.with_name(model.name + ".json").read_text(encoding="utf-8"))
    return note


def command_of(note: dict[str, object]) -> tuple[str, ...]:
    """The note's command line with ``MODEL`` (and ``OUT``) in place holders, whatever its age."""
    command = tuple(str(word) for word in note["command"])  # type: ignore[attr-defined]
    if "MODEL" in command:
        return command
    return (*command, "MODEL", *_OLD_OUTPUT.get(command[0], ()))


def case_of(model: Path) -> Case:
    """The saved input as the campaign ran it: its bytes or package, its command, its seed (the
    copy saved beside it for a diff, else the input itself, which gives the suffix)."""
    command = command_of(note_of(model))
    if model.is_dir():
        return Case(Seed(model, "fabric"), b"", command, tuple(sorted(read_package(model).items())))
    seed = model.with_name(model.name + ".seed" + model.suffix)
    return Case(Seed(seed if seed.is_file() else model, "replay"), model.read_bytes(), command)


def replay(model: Path) -> Outcome:
    with tempfile.TemporaryDirectory(prefix="earl-replay-") as folder:
        place = Path(folder)
        prepare_folder(place)
        return run_case(case_of(model), place)


def main(argv: list[str] | None = None) -> int:
    paths = [Path(arg) for arg in (sys.argv[1:] if argv is None else argv)]
    if not paths:
        print("usage: replay.py INPUT [INPUT ...]", file=sys.stderr)
        return 2
    failed = 0
    for path in paths:
        outcome = replay(path)
        for failure in outcome.failures:
            print(f"{path.name}: {failure.kind}: {failure.message}")
        failed += bool(outcome.failures)
        print(f"{path.name}: exit {outcome.code}, {len(outcome.failures)} failure(s), "
              f"peak {outcome.peak_kb / 1024:.0f} MiB", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

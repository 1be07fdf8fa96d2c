"""The fuzz campaign in the test suite: a short seeded run, the replay of every input that
once failed (``tests/fuzz/regressions``), and the properties shown to fail on made-up runs.

The short run is the first ``INPUTS`` inputs of seed ``SEED`` of ``tests/fuzz/runner.py`` (the
long campaign is ``make fuzz``): seeded mutations of the four sample dialects, the fixtures, the
corpus and the FABRIC examples, run through the command line in-process by two worker
processes, each input within a generous bound that only a hang exceeds. Every input must end in
an exit code of its command's table (``tests/fuzz/properties.EXIT_CODES``) without an internal
error, and hold the properties: a convert reads back as its source, a clean check lets every
target generate, the peak resident memory stays under 1 GiB. A failing input is written to
``tests/fuzz/failed/`` (git-ignored) with a note of its command; move it into
``tests/fuzz/regressions/`` with the fix. A replayed input is held to 30 s of CPU time.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from tests.fuzz import properties
from tests.fuzz.properties import EXIT_CODES, Run
from tests.fuzz.runner import REGRESSIONS, Campaign, Result, failures, seeds, summary

ROOT = Path(__file__).resolve().parents[1]

SEED = 20261124
INPUTS = 700  # each input runs more commands than a check: a clean check runs every target
CPU_SECONDS = 30  # what a replayed input may take (docs/untrusted-models.md)
FAILED = ROOT / "tests" / "fuzz" / "failed"
DIALECTS = {"papyrus", "cameo", "enterprise-architect", "sysml-v2"}
# Failures of earl-m2t the campaign found and that are not fixed yet: (class, a part of the
# message, what is wrong). The short run warns of each input they match (and writes it to
# tests/fuzz/failed/) instead of failing; remove an entry with its fix.
KNOWN_DEFECTS: tuple[tuple[str, str, str], ...] = (
)


def test_a_short_campaign_ends_every_input_as_its_command_allows_and_holds_the_properties() -> None:
    campaign = Campaign(SEED, seeds(), bound=120.0, jobs=2)
    results = campaign.run(0, INPUTS)
    assert [r.index for r in results] == list(range(INPUTS))
    assert {r.dialect for r in results} >= DIALECTS | {"fabric"}, summary(results)
    assert {r.command for r in results} == set(EXIT_CODES), summary(results)
    bad = failures(results)
    saved = [campaign.save(result, FAILED) for result in bad]
    known = [(r, path) for r, path in zip(bad, saved) if _known(r)]
    for result, path in known:  # shown in pytest's summary of warnings, never passed over in silence
        warnings.warn(f"known defect, not fixed yet: input {result.index} ({result.command}) {path.name}: "
                      f"{result.message[:300]}", stacklevel=1)
    unknown = [(r, path) for r, path in zip(bad, saved) if not _known(r)]
    assert not unknown, "\n".join(f"{r.command} {path}: {r.message}" for r, path in unknown) + \
        "\n" + summary(results)


def _known(result: Result) -> bool:
    """Every failure of the input is one of KNOWN_DEFECTS."""
    return all(any(kind == known_kind and text in message for known_kind, text, _ in KNOWN_DEFECTS)
               for kind, message in result.failures)


def _regressions() -> list[Path]:
    """Each input: a model file, or a FABRIC package's folder (not the notes, nor a diff's seed)."""
    return sorted(p for p in REGRESSIONS.iterdir() if not p.name.endswith(".json") and ".seed." not in p.name)


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
    resource.setrlimit(resource.RLIMIT_CPU, (CPU_SECONDS, CPU_SECONDS))


def test_the_regression_folder_holds_inputs_with_notes() -> None:
    inputs = _regressions()
    assert inputs
    for path in inputs:
        note = json.loads(path.with_name(path.name + ".json").read_text(encoding="utf-8"))
        assert note["command"] and note["command"][0] in EXIT_CODES, path.name
        assert "SEED" not in note["command"] or path.with_name(path.name + ".seed" + path.suffix).is_file(), path.name


@pytest.mark.parametrize("model", _regressions(), ids=lambda p: p.name)
def test_a_regression_input_holds_every_property_again(model: Path, tmp_path: Path) -> None:
    """The input through ``tests/fuzz/replay.py``: its command's exit code, and what follows from
    it (a clean check lets every target generate, a convert reads back, an import checks)."""
    result = subprocess.run([sys.executable, str(ROOT / "tests" / "fuzz" / "replay.py"), str(model)], cwd=tmp_path,
                            capture_output=True, text=True, timeout=CPU_SECONDS * 10, preexec_fn=_limited)
    assert result.returncode == 0 and not result.stdout.strip(), (result.stdout + result.stderr)[-2000:]


# Each property fails on a made-up run that breaks it, and holds on one that keeps it.

def test_the_contract_fails_on_an_internal_error_a_bad_exit_code_and_spin_refusing_the_promela() -> None:
    assert properties.contract(Run(("check", "m.uml"), 1, "m.uml:3: error: …")) is None
    assert properties.contract(Run(("verify", "m.uml"), 3, "not proven: the time bound")) is None
    internal = properties.contract(Run(("check", "m.uml"), 3, "earl-m2t: internal error: KeyError: '-'"))
    assert internal is not None and internal.kind == properties.INTERNAL and "KeyError" in internal.message
    escaped = properties.contract(Run(("show", "m.uml"), None, "escaped main: RecursionError"))
    assert escaped is not None and escaped.kind == properties.INTERNAL
    assert properties.contract(Run(("gen", "m.uml"), 0, "Traceback (most recent call last):")) is not None
    bad = properties.contract(Run(("check", "m.uml"), 3, "something"))
    assert bad is not None and bad.kind == properties.BAD_EXIT
    assert properties.contract(Run(("diff", "a", "b"), 4, "")) is not None
    spin = properties.contract(Run(("verify", "m.uml"), 2, "earl-m2t: spin -a failed: syntax error"))
    assert spin is not None and spin.kind == properties.SPIN


def test_the_round_trip_fails_when_the_converted_text_differs_or_cannot_be_read() -> None:
    assert properties.round_trip(Run(("diff", "m.uml", "c.sysml"), 0, "")) is None
    for code in (1, 2):
        failure = properties.round_trip(Run(("diff", "m.uml", "c.sysml"), code, "~ agent a: period"))
        assert failure is not None and failure.kind == properties.ROUND_TRIP


def test_check_then_gen_fails_when_a_target_refuses_a_model_check_passed() -> None:
    good = [Run(("gen", "--target", t, "m.uml"), 0, "") for t in ("cpp", "ros")]
    assert properties.check_then_gen(good) is None
    failure = properties.check_then_gen([*good, Run(("gen", "--target", "orocos", "m.uml"), 1, "error: …")])
    assert failure is not None and failure.kind == properties.CHECK_GEN and "orocos" in failure.message


def test_a_target_may_refuse_configurations_only_when_it_declares_it() -> None:
    refusal = ("earl-m2t: gen: --target ros2 does not switch configurations yet (the model has useA, useB); "
               "--target cpp runs a variable structure")
    refused = Run(("gen", "--target", "ros2", "m.uml"), 1, refusal)
    assert properties.check_then_gen([refused], frozenset({"ros2"})) is None
    assert properties.check_then_gen([refused]) is not None  # a target that does not declare it
    other = Run(("gen", "--target", "ros2", "m.uml"), 1, "earl-m2t: gen: 1 name(s) cannot become ROS names")
    assert properties.check_then_gen([other], frozenset({"ros2"})) is not None  # any other refusal


def test_the_memory_bound_fails_over_1_gib_for_an_input_under_10_mb() -> None:
    assert properties.memory(900 << 10, 5000) is None
    failure = properties.memory(1200 << 10, 5000)
    assert failure is not None and failure.kind == properties.MEMORY and "1200 MiB" in failure.message
    assert properties.memory(3 << 20, 11 << 20) is None  # the bound is for inputs under 10 MB


def test_the_peak_memory_of_an_input_is_measured_on_its_own() -> None:
    from tests.fuzz.memory import peak_kb, reset_peak

    ballast = bytearray(200 << 20)
    ballast[::4096] = b"x" * len(ballast[::4096])
    high = peak_kb()
    del ballast
    assert reset_peak(), "this kernel does not reset VmHWM through /proc/self/clear_refs"
    assert peak_kb() < high - (150 << 10)

"""The fuzz campaign in the test suite: a short seeded run, and the replay of every input that
once failed (``tests/fuzz/regressions``).

The short run is the first ``INPUTS`` inputs of seed ``SEED`` of ``tests/fuzz/runner.py`` (the
long campaign is ``make fuzz``): seeded mutations of the four sample dialects, the fixtures and
the corpus, run through the command line in-process by two worker processes, each input within
a generous bound that only a hang exceeds. Every input must end in exit 0, 1 or 2 without an
internal error. A failing input is written to ``tests/fuzz/failed/`` (git-ignored) with a note
of its command; move it into ``tests/fuzz/regressions/`` with the fix.
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
from pathlib import Path

import pytest

from tests.fuzz.runner import REGRESSIONS, Campaign, failures, seeds, summary

ROOT = Path(__file__).resolve().parents[1]

SEED = 20261124
INPUTS = 2400
FAILED = ROOT / "tests" / "fuzz" / "failed"
DIALECTS = {"papyrus", "cameo", "enterprise-architect", "sysml-v2"}


def test_a_short_campaign_ends_every_input_in_exit_0_1_or_2() -> None:
    campaign = Campaign(SEED, seeds(), bound=120.0, jobs=2)
    results = campaign.run(0, INPUTS)
    assert [r.index for r in results] == list(range(INPUTS))
    assert {r.dialect for r in results} >= DIALECTS, summary(results)
    bad = failures(results)
    saved = [campaign.save(result, FAILED) if result.code in (3, -1) else Path("-") for result in bad]
    assert not bad, "\n".join(f"{r.command} {path}: {r.message}" for r, path in zip(bad, saved)) + \
        "\n" + summary(results)


def _regressions() -> list[Path]:
    return sorted(p for p in REGRESSIONS.iterdir() if p.is_file() and not p.name.endswith(".json"))


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))


def test_the_regression_folder_holds_inputs_with_notes() -> None:
    inputs = _regressions()
    assert inputs
    for path in inputs:
        note = json.loads(path.with_name(path.name + ".json").read_text(encoding="utf-8"))
        assert note["command"] and note["command"][0] in ("check", "show", "convert", "gen"), path.name


@pytest.mark.parametrize("model", _regressions(), ids=lambda p: p.name)
def test_a_regression_input_ends_in_exit_0_1_or_2(model: Path, tmp_path: Path) -> None:
    command = json.loads(model.with_name(model.name + ".json").read_text(encoding="utf-8"))["command"]
    argv = [*command, str(model)]
    if command[0] == "gen":
        argv += ["-o", str(tmp_path / "out")]
    elif command[0] == "convert":
        argv += ["-o", str(tmp_path / "converted.sysml")]
    result = subprocess.run([sys.executable, "-m", "earl_m2t", *argv], cwd=tmp_path, capture_output=True, text=True,
                            timeout=300, preexec_fn=_limited)
    text = result.stdout + result.stderr
    assert result.returncode in (0, 1, 2), text[-2000:]
    assert "internal error" not in text and "Traceback" not in text, text[-2000:]

"""verify against the generated C++ on drawn variable-structure models (tests/support/random_switching.py).

For each drawn model, ``verify`` (the real SPIN) decides V006, "a switch can lose values", and
the model's generated C++ runs: deterministically with several seeds, each drawing its user
code's coins and the order of the subsystems' steps (``--schedule``), and threaded on the clock. The two must
agree:

* where verify proves "no switch loses values", no run reports a value undelivered at a switch;
* where verify finds a loss, its counterexample names the switch, the link and the state the
  leaving agent is stuck in; a deterministic run of the generated code must lose values on that
  link at that switch, forced with the agent in that state: a finding the code never shows
  would be a claim nobody can confirm.

The drawn models are the suite's ``differential switching`` campaign (tests/support/campaigns.toml):
``./dev test`` draws its ``suite`` count, ``./dev campaign`` its ``full`` count. They are checked
in shards, each its own xdist group, whose C++ is one CMake project built once per content. The
known-bad variant puts back the input semantics verify had before
:mod:`earl_m2t.analysis.receiving` (a state took every input of its buffer group, every input
without one): among the same models it must disagree with the generated code.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.model.elements import Buffer, State, Subsystem
from earl_m2t.verify import promela
from earl_m2t.verify.run import SWITCH_LOSES, VerifyOptions, verify_model
from tests.support import build_cache
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.cpp_sample import generate_with_user_code
from tests.support.random_switching import DrawnModel, draw, write

CAMPAIGN = "differential switching"  # tests/support/campaigns.toml
SHARDS = 4
SEEDS = 8  # deterministic runs per model: seed N draws the coins and the schedule (--schedule N; 0 model order)
CYCLES = 3000  # enough for every hand-over and a forced switch (200 cycles) after each
THREADED_SECONDS = 2.0
FIRST_SEED = 1000  # the drawn models are seeds FIRST_SEED, FIRST_SEED + 1, ...
PROVEN = "no switch loses values"
UNDELIVERED = re.compile(r"^link (\S+): (\d+) value\(s\) undelivered at switch$")
SWITCH = re.compile(r"^switch (\w+) -> (\w+) in [\d.]+ (?:cycles|ms)( \(forced\))?$")
LOSS = re.compile(r"the switch (\w+) → (\w+) ends by its timeout")
STEP = re.compile(r"^step \d+ ([\w/]+)\.cs: (?:start in|\w+ ->) (\w+)")
STUCK = re.compile(r"([\w/]+) stuck in [\w/.]+@(\w+)")


def models(shard: int) -> list[int]:
    """The seeds of the models ``shard`` checks."""
    return [FIRST_SEED + n for n in range(shard, loaded_runs(CAMPAIGN), SHARDS)]


@dataclass(frozen=True)
class Verdict:
    """What verify said about V006: "loss" (with the counterexample's switch, link and stuck
    state), "none" (proven) or "open" (the search was bounded)."""

    outcome: str
    switch: tuple[str, str] | None = None
    link: str = ""
    stuck: str = ""  # agent@state


def verdict(model: Path) -> Verdict:
    result = verify_model(load(model).model, VerifyOptions(timeout=120.0, checks=frozenset({SWITCH_LOSES})))
    finding = next((f for f in result.findings if f.code == SWITCH_LOSES), None)
    if finding is not None:
        switch = LOSS.search(finding.message)
        # the agent the lost values were for: the link's receiver, among the agents found stuck
        receiver = finding.element.split(",")[-1]
        stuck = next((m for m in STUCK.finditer(finding.message) if m.group(1) == receiver), None)
        return Verdict("loss", (switch.group(1), switch.group(2)) if switch else None, finding.element,
                       f"{stuck.group(1)}@{stuck.group(2)}" if stuck else "")
    if any(line.startswith(PROVEN) for line in result.proven):
        return Verdict("none")
    return Verdict("open")


@dataclass(frozen=True)
class Loss:
    """Values a switch reported undelivered on a link, and the state each agent was in then."""

    switch: tuple[str, str]
    link: str
    values: int
    states: tuple[tuple[str, str], ...]  # (agent, state)

    def shows(self, said: Verdict) -> bool:
        """This loss is the one ``said`` predicts: its link, its switch, its stuck agent's state."""
        if self.link != said.link or (said.switch is not None and self.switch != said.switch):
            return False
        agent, _, state = said.stuck.partition("@")
        return not agent or (agent, state) in self.states


@dataclass(frozen=True)
class Run:
    """One run of a model's generated system: what it lost at which switch."""

    label: str
    losses: tuple[Loss, ...]

    @property
    def lost(self) -> int:
        return sum(loss.values for loss in self.losses)

    @property
    def deterministic(self) -> bool:
        return self.label.startswith("deterministic")


def parse(label: str, output: str) -> Run:
    """The values each switch reported undelivered (the report comes before the switch's line),
    with the state each agent's control subsystem was in when the switch ended."""
    losses: list[Loss] = []
    pending: list[tuple[str, int]] = []
    states: dict[str, str] = {}
    for line in output.splitlines():
        if m := STEP.match(line):
            states[m.group(1)] = m.group(2)
        elif m := UNDELIVERED.match(line):
            pending.append((m.group(1), int(m.group(2))))
        elif m := SWITCH.match(line):
            now = tuple(sorted(states.items()))
            losses += [Loss((m.group(1), m.group(2)), link, n, now) for link, n in pending]
            pending = []
    return Run(label, tuple(losses))


def runs(binary: Path) -> list[Run]:
    """The deterministic runs, one per seed (its coins and its schedule), then a threaded one."""
    found = []
    for seed in range(SEEDS):
        env = {**os.environ, "EARL_DIFF_SEED": str(seed)}
        out = subprocess.run([str(binary), "--cycles", str(CYCLES), "--schedule", str(seed)], capture_output=True,
                             text=True, env=env, timeout=120, check=True).stdout
        found.append(parse(f"deterministic, seed {seed}", out))
    out = subprocess.run([str(binary), "--threaded", str(THREADED_SECONDS)], capture_output=True, text=True,
                         env={**os.environ, "EARL_DIFF_SEED": "7"}, timeout=120, check=True).stdout
    found.append(parse("threaded", out))
    return found


def disagreement(model: DrawnModel, said: Verdict, seen: list[Run]) -> str | None:
    """Why verify and the generated code disagree on ``model``, None when they agree."""
    if said.outcome == "none":
        losing = [r for r in seen if r.lost]
        if losing:
            shown = "; ".join(f"{r.label}: " + ", ".join(f"{loss.values} on {loss.link} at {loss.switch}"
                                                          for loss in r.losses) for r in losing)
            return f"verify proved {PROVEN!r}, the generated code lost values ({shown})\n{model.describe()}"
    elif said.outcome == "loss" and not any(r.deterministic and any(loss.shows(said) for loss in r.losses)
                                            for r in seen):
        shown = "; ".join(f"{r.label}: " + (", ".join(f"{loss.values} on {loss.link} at {loss.switch}"
                                                      for loss in r.losses) or "nothing lost") for r in seen)
        return (f"verify found a loss on {said.link} at the switch {said.switch}, {said.stuck} stuck; no "
                f"deterministic run of the generated code lost a value there in that state ({shown})\n"
                f"{model.describe()}")
    return None


# ------------------------------------------------------------------ the generated C++, built once per content

TOP = """cmake_minimum_required(VERSION 3.16)
project(drawn LANGUAGES CXX)
"""


def generated(model: DrawnModel, folder: Path) -> Path:
    """gen --target cpp of ``model`` over its user code, in ``folder/out``; the model file."""
    path = write(model, folder / "model")
    generate_with_user_code(path, folder / "model" / "user", folder / "out")
    return path


def built(drawn: list[DrawnModel], folder: Path) -> tuple[dict[int, Path], dict[int, Path]]:
    """(seed → model file, seed → executable): every model's C++ in one CMake project, each its
    own subdirectory, built once per content (tests/support/build_cache.py)."""
    source = folder / "project"
    files: dict[int, Path] = {}
    for model in drawn:
        files[model.seed] = generated(model, folder / str(model.seed))
        shutil.copytree(folder / str(model.seed) / "out", source / str(model.seed))
    source.mkdir(parents=True, exist_ok=True)
    (source / "CMakeLists.txt").write_text(TOP + "".join(f"add_subdirectory({m.seed})\n" for m in drawn))
    targets = [m.executable for m in drawn]
    configure = ["-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_CXX_COMPILER=g++"]

    def build(where: Path) -> None:
        for command in (["cmake", "-S", str(where / build_cache.SOURCE), "-B", str(where / "build"), *configure],
                        ["cmake", "--build", str(where / "build"), "-j", "2", "--target", *targets]):
            result = subprocess.run(command, capture_output=True, text=True, timeout=900)
            assert result.returncode == 0, f"{command[:2]} failed:\n{result.stdout[-4000:]}\n{result.stderr[-4000:]}"

    where = build_cache.built("cpp-drawn", source, build, ["cmake", *configure, *targets]) / "build"
    return files, {m.seed: where / str(m.seed) / m.executable for m in drawn}


# ------------------------------------------------------------------ the input semantics of before

def every_input_of_the_group(sub: Subsystem, state: State) -> tuple[Buffer, ...]:
    """What verify took a state to receive before earl_m2t.analysis.receiving: every input of
    its buffer group, every input of the subsystem when it has none."""
    group = next((g for g in sub.buffer_groups if g.name == state.activation.group), None)
    if group is None:
        return tuple(sub.inputs)
    names = {*group.obligatory, *group.optional}
    return tuple(b for b in sub.inputs if b.name in names or b.template in names)


@contextmanager
def old_input_semantics() -> Iterator[None]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(promela, "state_inputs", every_input_of_the_group)
        yield


def check(shard: int, folder: Path, stop_at_first: bool = False) -> tuple[list[str], Counter[str]]:
    """The disagreements on ``shard``'s models, and how many verify proved, found a loss in, or
    left open."""
    drawn = [draw(seed) for seed in models(shard)]
    files, binaries = built(drawn, folder)
    found: list[str] = []
    tally: Counter[str] = Counter()
    for model in drawn:
        said = verdict(files[model.seed])
        tally[said.outcome] += 1
        if said.outcome == "open":
            continue
        problem = disagreement(model, said, runs(binaries[model.seed]))
        if problem is not None:
            found.append(problem)
            if stop_at_first:
                break
    return found, tally


@pytest.mark.parametrize("shard", [pytest.param(k, marks=pytest.mark.xdist_group(f"differential {k}"))
                                   for k in range(SHARDS)])
def test_verify_and_the_generated_code_agree_on_drawn_models(
        shard: int, tmp_path: Path, record_property: Callable[[str, object], None]) -> None:
    found, tally = check(shard, tmp_path)
    summary = (f"shard {shard}: {len(models(shard))} models: verify proved {tally['none']}, found a loss in "
               f"{tally['loss']}, left {tally['open']} open; {len(found)} disagreement(s)")
    record_property("models", summary)  # in the JUnit XML, also from an xdist worker
    print(summary)
    assert tally["open"] <= len(models(shard)) // 10, tally
    assert not found, "\n\n".join(found)


@pytest.mark.xdist_group("differential 0")
def test_the_old_input_semantics_disagrees_with_the_generated_code(tmp_path: Path) -> None:
    """With a state taken to receive every input of its group, verify proves models lossless
    whose generated code loses values (a leaving worker waiting in a state that leaves its
    commands): the differential test fails within the models the suite draws."""
    with old_input_semantics():
        found: list[str] = []
        for shard in range(SHARDS):
            found += check(shard, tmp_path / str(shard), stop_at_first=True)[0]
            if found:
                break
    assert found, f"the old input semantics agreed with the generated code on all {catch_runs(CAMPAIGN)} models"
    assert PROVEN in found[0]

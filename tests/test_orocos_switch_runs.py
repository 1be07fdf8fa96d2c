"""The variable-structure samples on the Orocos target: ``samples/two_arm`` and
``samples/harmoniser`` generated with ``--target orocos`` over their shipped user code, built
against a real RTT 2.9 (tests/support/orocos.py) with warnings as errors, and deployed by OCL's
deployer (``deployer -s system.ops``) with every periodic master at 2 ms, one busy process per
CPU. The switch runs between components as earl/switch_protocol.hpp's rounds over RTT ports.

* two_arm, 50 deployments: every numbered command is taken exactly once, by the arm of the
  configuration it was sent in; no value undelivered at a switch, no overflow, no error in the
  output or OCL's log; the 20 switches of the C++ deterministic run, in its order, each within
  the switchTimeout; OCL connects exactly what the scripts say: the model's links (a variable
  link on its own ports) and, per master other than the coordinator, its command and
  acknowledgement connections;
* harmoniser, 50 deployments: the C++ run's switches; guide/a, resumed after the fall, goes on
  from its state and memory, fallHelp/a starts from its initial state; the same sample with
  guide/a restarted fails that check;
* sensitivity control: a build whose switch skips the drain (``-DEARL_SWITCH_DRAIN=0``) fails
  the two_arm checks in at least one of 50 deployments.

The deployer's stderr, where RTT's logger writes, is read apart from the lines the samples print:
the logger writes a line in pieces, and a sample's line landed inside one, lost to the checks.
Each deployment is stopped as soon as its last awaited line is printed. With ``-s`` the median
and worst switch latency of each sample's campaign are printed.
"""

from __future__ import annotations

import re
import shutil
import statistics
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.support import orocos
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.cpp_sample import cmake_build, generate_with_user_code, run
from tests.support.load import cpu_hogs, run_until
from tests.support.switch_checks import Harmoniser, TwoArm, forced_switches, forced_two_arm, restarted_harmoniser
from tests.support.switch_checks_orocos import (
    HARMONISER_SWITCHES,
    LEAD,
    assert_fall_help_starts_initially,
    assert_resumed,
    harmoniser_finished,
    latencies_ms,
    resume_index,
    switches,
    two_arm_finished,
    two_arm_problems,
)

ROOT = Path(__file__).resolve().parents[1]
TWO_ARM = ROOT / "samples" / "two_arm" / "two_arm.uml"
HARMONISER = ROOT / "samples" / "harmoniser" / "harmoniser.uml"
TWO_ARM_CAMPAIGN, HARMONISER_CAMPAIGN = "orocos two_arm", "orocos harmoniser"  # tests/support/campaigns.toml
TWO_ARM_RUNS = loaded_runs(TWO_ARM_CAMPAIGN)
HARMONISER_RUNS = loaded_runs(HARMONISER_CAMPAIGN)
PERIOD = 0.002  # s: every periodic master (the scripts' 0.01 s, as a user sets it)
RUN_TIMEOUT = 30.0  # s per deployment; one takes 2 to 4 s under load
ERROR = re.compile(r"\[\s*ERROR\s*\]")
CONNECTED = re.compile(r"Connected Port ([\w.]+) to\s+([\w.]+)\.")
CONNECT = re.compile(r'^connect\("([\w.]+)", "([\w.]+)", \w+\)$', re.M)
LOAD = re.compile(r'^loadComponent\("(\w+)", "[\w:]+"\)$', re.M)


@pytest.fixture(scope="module")
def rtt() -> orocos.Installation:
    """RTT and OCL; with ../shared/vendor/orocos a missing or failed build is a failure."""
    try:
        return orocos.installation()
    except orocos.OrocosBuildFailed as failure:
        pytest.fail(str(failure), pytrace=False)
    except orocos.OrocosUnavailable as reason:
        pytest.fail(str(reason), pytrace=False)


def generate(model: Path, user: Path, folder: Path, *options: str) -> Path:
    """gen --target orocos (gen's ``options`` added) over the sample's user code ``user`` copied
    into ``folder``."""
    shutil.copytree(user, folder / "user")
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "orocos", "-o",
                             str(folder), *options], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert not [line for line in result.stdout.splitlines() if line.startswith(("created ", "orphaned "))]
    return folder


def install(out: Path, rtt: orocos.Installation, *flags: str) -> Path:
    """The project built (warnings are errors, none printed) and installed; the prefix holding lib/orocos."""
    project = orocos.built_project(out, rtt, *flags)
    assert "warning:" not in (project / "build.log").read_text()
    return project / "install"


def installed(model: Path, rtt: orocos.Installation, folder: Path, *options: str) -> tuple[Path, Path]:
    """(gen's output, the install prefix) of ``model`` over its user code beside it, built once per
    content: tests/test_campaign_builds.py builds each model of this module among the parallel
    tests, so the loaded phase and this module's worker find them built."""
    out = generate(model, model.parent / "user", folder, *options)
    return out, install(out, rtt)


def forced_installed(rtt: orocos.Installation, folder: Path) -> tuple[Path, Path]:
    """two_arm with switchTimeout = 0.001 (every switch forced), generated with --force."""
    return installed(forced_two_arm(folder / "model"), rtt, folder / "out", "--force")


def restarted_installed(rtt: orocos.Installation, folder: Path) -> tuple[Path, Path]:
    """The harmoniser with guide/a restarted instead of resumed."""
    return installed(restarted_harmoniser(folder / "model"), rtt, folder / "out")


def deployment(out: Path, folder: Path) -> Path:
    """A copy of deploy/ whose periodic masters run every PERIOD."""
    shutil.copytree(out / "deploy", folder)
    for script in folder.glob("*.ops"):
        text = script.read_text()
        script.write_text(re.sub(r'^(setActivity\("\w+", )0\.01(, )', rf"\g<1>{PERIOD}\g<2>", text, flags=re.M))
    return folder


class Deployer:
    """Deployments of one build from one folder."""

    def __init__(self, deploy: Path, prefix: Path, rtt: orocos.Installation) -> None:
        self.deploy = deploy
        self.env = rtt.environment([prefix / "lib" / "orocos"])
        scripts = "\n".join(p.read_text() for p in sorted(deploy.glob("*.ops")))
        self.connects = sorted(CONNECT.findall(scripts))
        self.masters = LOAD.findall((deploy / "system.ops").read_text())

    def run(self, seen: Callable[[list[str]], bool]) -> tuple[list[str], list[str]]:
        """One deployment, stopped once ``seen``; (its output, what goes wrong besides the sample's checks)."""
        stderr = self.deploy / "deployer.stderr"
        lines, ok = run_until(["deployer", "-l", "info", "-s", "system.ops"], seen, RUN_TIMEOUT, self.env,
                              cwd=self.deploy, graceful=False, stderr=stderr)
        found = [] if ok else [f"not done in {RUN_TIMEOUT} s: " + " | ".join(lines[-5:])]
        log = (self.deploy / "orocos.log").read_text(errors="replace").splitlines()
        logged = lines + stderr.read_text(errors="replace").splitlines() + log
        found += [line for line in logged if ERROR.search(line) or "value sent is lost" in line][:3]
        connected = sorted((m.group(1), m.group(2)) for m in map(CONNECTED.search, log) if m)
        if connected != self.connects:
            found.append(f"{len(connected)} connections made, the scripts make {len(self.connects)}")
        return lines, found


def report(sample: str, latencies: list[float]) -> None:
    print(f"\n{sample}: {len(latencies)} switches, latency median {statistics.median(latencies):.3f} ms, "
          f"worst {max(latencies):.3f} ms")


# ---------------------------------------------------------------- two_arm


@pytest.fixture(scope="module")
def two_arm(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return generate(TWO_ARM, TWO_ARM.parent / "user", tmp_path_factory.mktemp("two_arm_orocos"))


@pytest.fixture(scope="module")
def two_arm_cpp_switches(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[str, str]]:
    """The switches of the C++ target's deterministic run."""
    folder = tmp_path_factory.mktemp("two_arm_cpp")
    binary = cmake_build(generate_with_user_code(TWO_ARM, TWO_ARM.parent / "user", folder / "out"),
                         "TwoArm_system")
    found = switches(run(binary, "--cycles", "6000").splitlines())
    assert len(found) == 20
    return found


@pytest.mark.loaded
def test_two_arm_deployments_under_load_hand_every_command_over(
        two_arm: Path, rtt: orocos.Installation, two_arm_cpp_switches: list[tuple[str, str]], tmp_path: Path) -> None:
    deployer = Deployer(deployment(two_arm, tmp_path / "deploy_2ms"), install(two_arm, rtt), rtt)
    system_connects = CONNECT.findall((two_arm / "deploy" / "system.ops").read_text())
    # the model's 4 links (all variable), and per master but the coordinator task/a.cs its 2 control ports
    assert len(system_connects) == 4 + 2 * (len(deployer.masters) - 1) and len(deployer.masters) == 3
    failures, latencies = [], []
    with cpu_hogs():
        for attempt in range(1, TWO_ARM_RUNS + 1):
            lines, found = deployer.run(lambda out: two_arm_finished(out, "task_a_cs"))
            found += two_arm_problems(lines) + TwoArm.not_reset_at_restart(lines)
            if switches(lines) != two_arm_cpp_switches:
                found.append(f"switches {switches(lines)}")
            latencies += latencies_ms(lines)
            if found:
                failures.append(f"run {attempt}: {found}")
    report("two_arm", latencies)
    assert not failures, f"{len(failures)} of {TWO_ARM_RUNS} deployments failed:\n" + "\n".join(failures[:5])


@pytest.mark.loaded
def test_the_checks_catch_a_switch_that_skips_the_drain(two_arm: Path, rtt: orocos.Installation,
                                                        tmp_path: Path) -> None:
    prefix = install(two_arm, rtt, "-DEARL_SWITCH_DRAIN=0")
    deployer = Deployer(deployment(two_arm, tmp_path / "deploy_undrained"), prefix, rtt)
    with cpu_hogs():
        caught = next((attempt for attempt in range(1, catch_runs(TWO_ARM_CAMPAIGN) + 1)
                       if two_arm_problems(deployer.run(lambda out: two_arm_finished(out, "task_a_cs"))[0])), None)
    assert caught is not None, (f"all {catch_runs(TWO_ARM_CAMPAIGN)} deployments of the drain-skipping build "
                                "passed the checks")


def test_forced_switches_name_every_command_they_lose(rtt: orocos.Installation, tmp_path: Path) -> None:
    """two_arm with switchTimeout = 0.001 (below a master's 2 ms period): the switches are forced,
    and every command is taken or named undelivered by the manipulator's master (the one it had
    taken and not yet processed too), the coordinator's counts adding up."""
    out, prefix = forced_installed(rtt, tmp_path / "forced")
    deployer = Deployer(deployment(out, tmp_path / "deploy"), prefix, rtt)
    lines, _ = deployer.run(lambda seen: two_arm_finished(seen, "task_a_cs"))
    assert forced_switches(lines) > 0, lines[-20:]
    assert TwoArm.unreconciled(lines) == [], lines[-20:]
    named = sum(1 for line in lines if TwoArm.NAMED.match(line))
    print(f"two_arm forced: {forced_switches(lines)} forced switches, {named} commands named undelivered")


# ---------------------------------------------------------------- harmoniser


@pytest.fixture(scope="module")
def harmoniser_cpp_switches(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[str, str]]:
    folder = tmp_path_factory.mktemp("harmoniser_cpp")
    binary = cmake_build(generate_with_user_code(HARMONISER, HARMONISER.parent / "user", folder / "out"),
                         "Harmoniser_system")
    return switches(run(binary, "--cycles", "230").splitlines())


@pytest.mark.loaded
def test_harmoniser_deployments_under_load_resume_the_guide_agent(
        tmp_path_factory: pytest.TempPathFactory, rtt: orocos.Installation,
        harmoniser_cpp_switches: list[tuple[str, str]], tmp_path: Path) -> None:
    assert harmoniser_cpp_switches == HARMONISER_SWITCHES
    out, prefix = installed(HARMONISER, rtt, tmp_path_factory.mktemp("harmoniser_orocos"))
    deployer = Deployer(deployment(out, tmp_path / "deploy_2ms"), prefix, rtt)
    failures, latencies = [], []
    with cpu_hogs():
        for attempt in range(1, HARMONISER_RUNS + 1):
            lines, found = deployer.run(harmoniser_finished)
            if switches(lines) != harmoniser_cpp_switches:
                found.append(f"switches {switches(lines)}")
            found += [line for line in lines if "undelivered at switch" in line or "overflowed" in line]
            found += Harmoniser.commands_not_taken_once(lines)  # what guide/a sent until it stopped included
            try:
                assert_resumed(lines, "guide_a_cs")
                assert_fall_help_starts_initially(lines, "fallHelp_a_cs")
            except (AssertionError, StopIteration, ValueError) as failed:
                found.append(f"guide/a or fallHelp/a: {failed!r}")
            latencies += latencies_ms(lines)
            if found:
                failures.append(f"run {attempt}: {found}")
    report("harmoniser", latencies)
    assert not failures, f"{len(failures)} of {HARMONISER_RUNS} deployments failed:\n" + "\n".join(failures[:5])


def test_a_restarted_guide_agent_fails_the_checks(tmp_path: Path, rtt: orocos.Installation) -> None:
    out, prefix = restarted_installed(rtt, tmp_path / "restarted")
    deployer = Deployer(deployment(out, tmp_path / "deploy_2ms"), prefix, rtt)
    lines, found = deployer.run(harmoniser_finished)
    assert not found and switches(lines) == HARMONISER_SWITCHES, found
    assert next(m for m in map(LEAD.match, lines[resume_index(lines):]) if m).group(1) == "1"
    with pytest.raises(AssertionError):
        assert_resumed(lines, "guide_a_cs")


"""The variable-structure samples run as ROS 2 nodes: ``samples/two_arm`` and
``samples/harmoniser`` generated with ``--target ros2`` over their shipped user code, built with
colcon against the ROS 2 Jazzy of tests/support/ros2.py and launched (bringup
``system.launch.py``, ``period:=0.001``) with one busy process per CPU, each launch on a ROS
domain of its own. Every node is an ``earl::SwitchMember`` over /earl/switch and
/earl/switch_ack (the coordinator's node runs the ``earl::SwitchCoordinator``); each variable
link is its own topic, ``<output topic>/<link>``. A launch stops as soon as the run has shown what the checks need.

* the wiring: each node's switch parameters and topics are switch_wiring's numbering, as for
  ROS 1; a model without configurations gets no switch;
* two_arm, composed (a container per agent) and a process per node: every numbered command
  taken exactly once, by the arm of the configuration it was sent in; nothing undelivered; 20
  switches, each within switchTimeout; the C++ deterministic run's sequence of switches;
* harmoniser, composed and a process per node: guiding -> fallResponse -> guiding within the
  timeouts, nothing undelivered, the resumed guide agent goes on from its state and memory,
  fallHelp/a starts from its initial state; the harmoniser with guide/a restarted instead of
  resumed leads from the first waypoint again, which the checks of the resumed agent reject;
* sensitivity: a build that skips the drain (``-DEARL_SWITCH_DRAIN=0``) fails the two_arm
  checks within the launches its campaign keeps (campaign.catch_runs).

Run with ``-s`` for the switch latencies (median and worst) and the launch times.
"""

from __future__ import annotations

import ast
import random
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import render
from earl_m2t.gen.views.switch_wiring import switch_wiring
from tests.support import ros2
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs, run_until
from tests.support.switch_checks import (
    Harmoniser,
    TwoArm,
    beyond_timeout,
    cpp_trace,
    forced_switches,
    forced_two_arm,
    latencies_ms,
    latency_summary,
    notable,
    restarted_harmoniser,
    switch_timeouts_ms,
    switches,
    undelivered,
)

ROOT = Path(__file__).resolve().parents[1]
# the ROS 2 modules share one worker of a parallel run: two launches at once could meet on a ROS domain
pytestmark = pytest.mark.xdist_group("ros2")
TWO_ARM = ROOT / "samples" / "two_arm" / "two_arm.uml"
HARMONISER = ROOT / "samples" / "harmoniser" / "harmoniser.uml"
# the loaded campaigns (tests/support/campaigns.toml), composed or a process per node
TWO_ARM_CAMPAIGNS = {"true": "ros2 two_arm", "false": "ros2 two_arm processes"}
HARMONISER_CAMPAIGNS = {"true": "ros2 harmoniser", "false": "ros2 harmoniser processes"}
LAUNCH_TIMEOUT = 90.0  # s per launch: start-up of the containers (or processes) under load, then the script
WAYPOINTS_BACK = 5  # the harmoniser's launch stops once guide/a led to this many waypoints back in guiding
PREFIX = re.compile(r"^\[[^\]]+\] ")  # launch prefixes each line of a process with "[<process>] "

Lines = list[str]


# ------------------------------------------------------------------ the generated wiring

def launch_table(files: dict[str, bytes]) -> dict[str, tuple[dict[str, object], list[tuple[str, str]]]]:
    """(parameters from its agent's parameter file, remaps of the generated system launch file)
    of every node, by its model path."""
    [(launch_path, content)] = [(p, c) for p, c in files.items() if p.endswith("_bringup/launch/system.launch.py")]
    bringup = launch_path.removesuffix("launch/system.launch.py")
    tree = ast.parse(content.decode())
    value = next(node.value for node in tree.body if isinstance(node, ast.Assign)
                 and any(isinstance(t, ast.Name) and t.id == "AGENTS" for t in node.targets))
    table: dict[str, tuple[dict[str, object], list[tuple[str, str]]]] = {}
    for namespace, _, parameter_file, nodes in ast.literal_eval(value):
        values = ros2.parameters_of_text(files[bringup + parameter_file].decode(), parameter_file)
        for _, _, _, name, remaps in nodes:
            parameters = values[f"/{namespace}/{name}"]
            table[str(parameters["path"])] = (parameters, remaps)
    return table


@pytest.mark.parametrize("sample", [TWO_ARM, HARMONISER], ids=["two_arm", "harmoniser"])
def test_each_variable_link_is_a_topic_of_its_own_and_each_node_is_wired_as_the_switch_numbers_it(
        sample: Path) -> None:
    model = load(sample).model
    wiring = switch_wiring(model)
    assert wiring is not None
    files = render(model, "ros2").generated
    nodes = launch_table(files)
    assert sorted(nodes) == sorted(n.path for n in wiring.nodes)
    for n in wiring.nodes:
        params, _ = nodes[n.path]
        assert (params["switch_node"], params["switch_agent"], params["switch_nodes"]) == (
            n.index, n.agent, len(wiring.nodes))
        assert params["switch_control"] is n.control
        assert params["switch_coordinator"] is n.coordinator
        received = sorted(int(str(v)) for k, v in params.items() if k.endswith("_switch_link"))
        assert received == sorted(n.receives)
        sent = sorted(int(item.partition(":")[0]) for k, v in params.items() if k.endswith("_switch_links")
                      for item in str(v).split())
        assert sent == sorted(n.sends)
        # each variable link's topic is one the node waits for (its link count)
        for k, v in params.items():
            if k.endswith("_switch_links"):
                output = k.removesuffix("_switch_links")
                for item in str(v).split():
                    assert params[f"{output}__{item.partition(':')[2]}_links"] == 1
    remaps = [to for _, node_remaps in nodes.values() for _, to in node_remaps]
    assert not [r for r in remaps if "__" in r]  # ROS 2 refuses a repeated underscore in a name
    variable = [r for r in remaps if r.count("/") == 4]  # /<agent>/<subsystem>/<output>/<link>
    assert len(set(variable)) == len(variable) == len(wiring.links)  # a topic per variable link
    for n in wiring.nodes:  # each onto a variable link its sender sends
        params, _ = nodes[n.path]
        for k, v in params.items():
            if k.endswith("_switch_links"):
                for item in str(v).split():
                    assert any(r.endswith(f"/{k.removesuffix('_switch_links')}/{item.partition(':')[2]}")
                               for r in variable)
    assert len(remaps) - len(variable) == len(model.links) - len(wiring.links)  # the fixed links: as before
    msgs = {path.rpartition("/")[2] for path in files if path.endswith(".msg")}
    assert {"EarlSwitch.msg", "EarlSwitchAck.msg"} <= msgs
    components = [c for p, c in files.items() if p.endswith("_component.cpp")]
    assert components and all(b"earl/switch_protocol.hpp" in c and b"declare_parameter<bool>(\"switch_coordinator\""
                                  in c for c in components)


def test_a_model_without_configurations_gets_no_switch() -> None:
    files = render(load(ROOT / "samples" / "pick_and_place" / "pick_and_place.uml").model, "ros2").generated
    assert not [path for path in files if "EarlSwitch" in path or path.endswith("switch_protocol.hpp")]
    assert not [path for path, content in files.items() if b"switch_node" in content or b"/earl/switch" in content]


# ------------------------------------------------------------------ building and launching

@pytest.fixture(scope="module")
def jazzy() -> ros2.Installation:
    """The ROS 2 prefix of tests/support/ros2.py (a missing build fails, never skips, when
    ../shared/vendor/ros2 is there)."""
    return ros2.installation_for_tests()


def gen(model: Path, ws: Path, user: Path | None = None, *options: str) -> None:
    """A colcon workspace whose src/ is gen's output for ``model`` (gen's ``options`` added), its
    shipped user code (``user``, else the one beside the model) first; gen again over a workspace
    keeps its user code."""
    shutil.copytree(user or model.parent / "user", ws / "src" / "user", dirs_exist_ok=True)
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "ros2", "-o",
                             str(ws / "src"), *options], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr


def build(jazzy: ros2.Installation, ws: Path, *cmake_flags: str) -> Path:
    """``colcon build`` with the flags of tests/support/ros2.py (``cmake_flags`` added to its C++
    flags), once per content: the built workspace."""
    return jazzy.colcon_build(ws, *cmake_flags)


def undrained_built(jazzy: ros2.Installation, ws: Path) -> Path:
    """two_arm built with the drain skipped (test-only), the known-bad variant of its campaigns
    (built once per content: tests/test_campaign_builds.py builds it among the parallel tests)."""
    gen(TWO_ARM, ws)
    return build(jazzy, ws, "-DEARL_SWITCH_DRAIN=0")


# The workspaces this module launches, each built once per content: tests/test_campaign_builds.py
# builds them among the parallel tests, so the loaded phase and this module's worker find them built.

def two_arm_built(jazzy: ros2.Installation, ws: Path) -> Path:
    gen(TWO_ARM, ws)
    return build(jazzy, ws)


def harmoniser_built(jazzy: ros2.Installation, ws: Path) -> Path:
    gen(HARMONISER, ws)
    return build(jazzy, ws)


def forced_built(jazzy: ros2.Installation, folder: Path) -> Path:
    """two_arm with switchTimeout = 0.001 (every switch forced), generated with --force."""
    model = forced_two_arm(folder / "model")
    gen(model, folder / "ws", None, "--force")
    return build(jazzy, folder / "ws")


def restarted_built(jazzy: ros2.Installation, folder: Path) -> Path:
    """The harmoniser with guide/a restarted instead of resumed."""
    gen(restarted_harmoniser(folder / "model"), folder / "ws", HARMONISER.parent / "user")
    return build(jazzy, folder / "ws")


@pytest.fixture(scope="module")
def two_arm(tmp_path_factory: pytest.TempPathFactory, jazzy: ros2.Installation) -> Path:
    return two_arm_built(jazzy, tmp_path_factory.mktemp("two_arm_ros2_ws"))


@pytest.fixture(scope="module")
def harmoniser(tmp_path_factory: pytest.TempPathFactory, jazzy: ros2.Installation) -> Path:
    return harmoniser_built(jazzy, tmp_path_factory.mktemp("harmoniser_ros2_ws"))


def launch(ws: Path, jazzy: ros2.Installation, folder: Path, seen: Callable[[Lines], bool], composed: str = "true"
           ) -> tuple[Lines, bool, float]:
    """One launch of the system until ``seen``, on a ROS domain of its own: (its output without
    launch's process prefixes, whether seen, seconds)."""
    bringup = next(p.parent.name for p in (ws / "src").glob("*_bringup/package.xml"))
    env = jazzy.environment(ws, domain_id=random.randint(1, 100))
    env.update(ROS_LOG_DIR=str(folder / "log"), ROS_HOME=str(folder / "home"))
    started = time.monotonic()
    lines, reached = run_until(["ros2", "launch", bringup, "system.launch.py", "period:=0.001",
                                f"composed:={composed}"],
                               lambda out: seen([PREFIX.sub("", line.strip()) for line in out]), LAUNCH_TIMEOUT, env)
    return [PREFIX.sub("", line.strip()) for line in lines], reached, time.monotonic() - started


def report(sample: str, latencies: list[float], seconds: list[float]) -> None:
    print(f"\n{sample}: {len(seconds)} launches, {latency_summary(latencies)}; launch median "
          f"{sorted(seconds)[len(seconds) // 2]:.2f} s, longest {max(seconds):.2f} s")


# ------------------------------------------------------------------ two_arm

def two_arm_problems(lines: Lines, reached: bool, expected: list[tuple[str, str]], timeouts: dict[str, float]
                     ) -> list[str]:
    found = TwoArm.problems(lines) + beyond_timeout(lines, timeouts)
    if not reached:
        found.append("the run did not finish")
    if switches(lines) != expected:
        found.append(f"switches {switches(lines)} are not the C++ run's")
    return found


@pytest.fixture(scope="module")
def two_arm_switches(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[str, str]]:
    trace = cpp_trace(TWO_ARM, tmp_path_factory.mktemp("two_arm_cpp"), "TwoArm_system", 6000)
    assert TwoArm.problems(trace) == []
    return switches(trace)


@pytest.mark.loaded
@pytest.mark.parametrize("composed", ["true", "false"])
def test_two_arm_launches_under_load_hand_every_command_over(
        two_arm: Path, jazzy: ros2.Installation, two_arm_switches: list[tuple[str, str]], tmp_path: Path,
        composed: str) -> None:
    runs = loaded_runs(TWO_ARM_CAMPAIGNS[composed])
    timeouts = switch_timeouts_ms(two_arm)
    failures: list[str] = []
    latencies: list[float] = []
    seconds: list[float] = []
    with cpu_hogs():
        for attempt in range(runs):
            lines, reached, took = launch(two_arm, jazzy, tmp_path, TwoArm.finished, composed)
            seconds.append(took)
            latencies += latencies_ms(lines)
            found = two_arm_problems(lines, reached, two_arm_switches, timeouts)
            if found:
                failures.append(f"launch {attempt + 1}: {found}\n{notable(lines)}")
    report(f"two_arm (ros2, composed={composed})", latencies, seconds)
    assert not failures, f"{len(failures)} of {runs} launches failed:\n" + "\n".join(failures[:2])


@pytest.mark.loaded
@pytest.mark.parametrize("composed", ["true", "false"])
def test_two_arm_checks_catch_a_build_that_skips_the_drain(
        tmp_path_factory: pytest.TempPathFactory, jazzy: ros2.Installation,
        two_arm_switches: list[tuple[str, str]], tmp_path: Path, composed: str) -> None:
    ws = undrained_built(jazzy, tmp_path_factory.mktemp("two_arm_ros2_undrained_ws"))
    timeouts = switch_timeouts_ms(ws)
    runs = catch_runs(TWO_ARM_CAMPAIGNS[composed])
    caught = None
    with cpu_hogs():
        for attempt in range(runs):
            lines, reached, _ = launch(ws, jazzy, tmp_path, TwoArm.finished, composed)
            found = two_arm_problems(lines, reached, two_arm_switches, timeouts)
            if found:
                caught = f"launch {attempt + 1}: {found}"
                break
    print(f"\ntwo_arm (ros2, composed={composed}) without the drain: {caught}")
    assert caught is not None, f"all {runs} launches of the drain-skipping build passed the checks"


def test_forced_switches_name_every_command_they_lose(
        tmp_path_factory: pytest.TempPathFactory, jazzy: ros2.Installation, tmp_path: Path) -> None:
    """two_arm with switchTimeout = 0.001: the switches are forced, and every command is taken
    or named undelivered by the manipulator's node (the one it had taken and not yet processed
    too), the coordinator's counts adding up."""
    ws = forced_built(jazzy, tmp_path_factory.mktemp("two_arm_forced"))
    lines, reached, _ = launch(ws, jazzy, tmp_path, TwoArm.finished)
    assert reached, notable(lines)
    assert forced_switches(lines) > 0, notable(lines)
    assert TwoArm.unreconciled(lines) == [], notable(lines)
    named = sum(1 for line in lines if TwoArm.NAMED.match(line))
    print(f"two_arm forced: {forced_switches(lines)} forced switches, {named} commands named undelivered")


# ------------------------------------------------------------------ harmoniser

def back_in_guiding(lines: Lines) -> bool:
    """The switch back to guiding was printed, guide/a has led to a few waypoints since, and
    tiago/a has taken a command of guide/a's again (the third run of its numbers)."""
    back = next((i for i, line in enumerate(lines) if line.startswith("switch fallResponse -> guiding")), None)
    return (back is not None and sum(1 for line in lines[back:] if Harmoniser.LEAD.match(line)) >= WAYPOINTS_BACK
            and len(Harmoniser.taken_runs(lines)) >= 3)


def harmoniser_problems(lines: Lines, reached: bool, expected: list[tuple[str, str]],
                        timeouts: dict[str, float]) -> list[str]:
    found = undelivered(lines) + beyond_timeout(lines, timeouts)
    if not reached:
        return [*found, f"the run did not come back to guiding: switches {switches(lines)}"]
    if switches(lines) != expected:
        found.append(f"switches {switches(lines)} are not the C++ run's")
    return found + [problem for problem in Harmoniser.problems(lines) if problem not in found]


@pytest.fixture(scope="module")
def harmoniser_switches(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[str, str]]:
    trace = cpp_trace(HARMONISER, tmp_path_factory.mktemp("harmoniser_cpp"), "Harmoniser_system", 230)
    assert switches(trace) == Harmoniser.SWITCHES
    return switches(trace)


@pytest.mark.loaded
@pytest.mark.parametrize("composed", ["true", "false"])
def test_harmoniser_launches_under_load_resume_the_guide_agent(
        harmoniser: Path, jazzy: ros2.Installation, harmoniser_switches: list[tuple[str, str]], tmp_path: Path,
        composed: str) -> None:
    runs = loaded_runs(HARMONISER_CAMPAIGNS[composed])
    timeouts = switch_timeouts_ms(harmoniser)
    failures: list[str] = []
    latencies: list[float] = []
    seconds: list[float] = []
    with cpu_hogs():
        for attempt in range(runs):
            lines, reached, took = launch(harmoniser, jazzy, tmp_path, back_in_guiding, composed)
            seconds.append(took)
            latencies += latencies_ms(lines)
            found = harmoniser_problems(lines, reached, harmoniser_switches, timeouts)
            if found:
                failures.append(f"launch {attempt + 1}: {found}\n{notable(lines)}")
    report(f"harmoniser (ros2, composed={composed})", latencies, seconds)
    assert not failures, f"{len(failures)} of {runs} launches failed:\n" + "\n".join(failures[:2])


def test_a_restarted_guide_agent_starts_from_the_initial_state_and_fails_the_checks(
        jazzy: ros2.Installation, harmoniser_switches: list[tuple[str, str]], tmp_path: Path) -> None:
    """The harmoniser generated from the model with guide/a restarted instead of resumed, and built."""
    ws = restarted_built(jazzy, tmp_path / "restarted")
    lines, reached, _ = launch(ws, jazzy, tmp_path, back_in_guiding)
    assert reached and switches(lines) == harmoniser_switches and not undelivered(lines), notable(lines)
    assert Harmoniser.first_waypoint_back(lines) == 1
    assert any(Harmoniser.GUIDE_START.match(line) for line in lines[Harmoniser.resumed_at(lines)[1]:])
    with pytest.raises(AssertionError):
        Harmoniser.assert_resumed(lines)

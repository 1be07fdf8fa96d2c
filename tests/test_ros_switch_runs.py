"""The variable-structure samples run as ROS 1 nodes: ``samples/two_arm`` and
``samples/harmoniser`` generated with ``--target ros`` over their shipped user code, built with
catkin_make and launched (bringup ``system.launch``, ``period:=0.001``) 50 times each with one
busy process per CPU, one roscore serving every launch. Each node takes part in the switch of
earl/switch_protocol.hpp over /earl/switch and /earl/switch_ack; each variable link is its own
topic. A launch stops as soon as the run has shown what the checks need.

* two_arm, 50 of 50 launches: every numbered command taken exactly once, by the arm of the
  configuration it was sent in; no value undelivered; 20 switches, each within switchTimeout;
* harmoniser, 50 of 50: guiding -> fallResponse -> guiding, each switch within its timeout,
  nothing undelivered; the resumed guide agent goes on from its state and memory, fallHelp/a
  starts from its initial state;
* both: the sequence of switches is the C++ deterministic run's;
* sensitivity: a build that skips the drain (``-DEARL_SWITCH_DRAIN=0``) fails the two_arm
  checks in one of at most 50 launches; the harmoniser with guide/a restarted instead of
  resumed leads from the first waypoint again, which the checks of the resumed agent reject.

Run with ``-s`` for the switch latencies (median and worst) and the launch times.
"""

from __future__ import annotations

import statistics
import time
import xml.etree.ElementTree as ElementTree
import xmlrpc.client
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import render
from earl_m2t.gen.views.switch_wiring import switch_wiring
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs, run_until
from tests.support.ros_launch import (
    catkin_make,
    clear_start_barrier,
    environment,
    forget_nodes,
    generate,
    needs_catkin,
    needs_roslaunch,
    roscore,
)
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
TWO_ARM = ROOT / "samples" / "two_arm" / "two_arm.uml"
HARMONISER = ROOT / "samples" / "harmoniser" / "harmoniser.uml"
TWO_ARM_CAMPAIGN, HARMONISER_CAMPAIGN = "ros two_arm", "ros harmoniser"  # tests/support/campaigns.toml
TWO_ARM_RUNS = loaded_runs(TWO_ARM_CAMPAIGN)
HARMONISER_RUNS = loaded_runs(HARMONISER_CAMPAIGN)
LAUNCH_TIMEOUT = 30.0  # s per launch: start-up of the nodes under load, then well under a second of script
WAYPOINTS_BACK = 5  # the harmoniser's launch stops once guide/a led to this many waypoints back in guiding


def launched(test: Callable[..., None]) -> Callable[..., None]:
    """A test that builds with catkin_make and launches with roslaunch."""
    return needs_catkin(needs_roslaunch(test))


Lines = list[str]


@pytest.fixture(scope="module")
def core(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Path, int, xmlrpc.client.ServerProxy]]:
    """(the ROS home, the port, the master) of the one roscore of the module."""
    home = tmp_path_factory.mktemp("ros_home")
    with roscore(home) as (port, master):
        yield home, port, master


def workspace(folder: Path, model: Path, *flags: str) -> Path:
    generate(model, model.parent / "user", folder)
    return catkin_make(folder, *flags)


def undrained_built(folder: Path) -> Path:
    """two_arm built with the drain skipped (test-only), the known-bad variant of its campaign
    (built once per content: tests/test_campaign_builds.py builds it among the parallel tests)."""
    return workspace(folder, TWO_ARM, "-DCMAKE_CXX_FLAGS=-DEARL_SWITCH_DRAIN=0")


def forced_built(folder: Path) -> Path:
    """two_arm with switchTimeout = 0.001 (every switch forced), generated with --force and built
    (once per content: tests/test_campaign_builds.py builds it among the parallel tests)."""
    model = forced_two_arm(folder / "model")
    generate(model, model.parent / "user", folder / "ws", "--force")
    return catkin_make(folder / "ws")


def restarted_built(folder: Path) -> Path:
    """The harmoniser with guide/a restarted instead of resumed, built (once per content)."""
    return workspace(folder / "ws", restarted_harmoniser(folder / "model"))


@pytest.fixture(scope="module")
def two_arm(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return workspace(tmp_path_factory.mktemp("two_arm_ws"), TWO_ARM)


@pytest.fixture(scope="module")
def harmoniser(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return workspace(tmp_path_factory.mktemp("harmoniser_ws"), HARMONISER)


def launch(ws: Path, core: tuple[Path, int, xmlrpc.client.ServerProxy], seen: Callable[[Lines], bool]
           ) -> tuple[Lines, bool, float]:
    """One launch of the system until ``seen``: (its output, stripped, whether seen, seconds)."""
    home, port, master = core
    clear_start_barrier(master)  # first: it waits for the master, which may still be starting
    forget_nodes(master)  # the previous launch's, killed without unregistering
    bringup = next(p.parent.name for p in (ws / "src").glob("*_bringup/package.xml"))
    started = time.monotonic()
    lines, reached = run_until(["roslaunch", "--wait", bringup, "system.launch", "period:=0.001"],
                               lambda out: seen([line.strip() for line in out]), LAUNCH_TIMEOUT,
                               environment(ws, home, port), graceful=False)
    return [line.strip() for line in lines], reached, time.monotonic() - started


def report(sample: str, latencies: list[float], seconds: list[float]) -> None:
    print(f"\n{sample}: {len(seconds)} launches, {latency_summary(latencies)}; launch median "
          f"{statistics.median(seconds):.2f} s, longest {max(seconds):.2f} s")


# ------------------------------------------------------------------ the generated wiring

def launch_nodes(files: dict[str, bytes]) -> dict[str, ElementTree.Element]:
    """Every <node> of the agents' launch files, by its model path."""
    nodes = {}
    for path, content in files.items():
        if path.endswith(".launch") and "_bringup/" not in path:
            for node in ElementTree.fromstring(content).iter("node"):
                params = {p.get("name"): p.get("value") for p in node.iter("param")}
                nodes[str(params["path"])] = node
    return nodes


@pytest.mark.parametrize("sample", [TWO_ARM, HARMONISER], ids=["two_arm", "harmoniser"])
def test_each_variable_link_is_a_topic_of_its_own_and_each_node_is_wired_as_the_switch_numbers_it(
        sample: Path) -> None:
    model = load(sample).model
    wiring = switch_wiring(model)
    assert wiring is not None
    files = render(model, "ros").generated
    nodes = launch_nodes(files)
    assert sorted(nodes) == sorted(n.path for n in wiring.nodes)
    for n in wiring.nodes:
        params = {p.get("name"): p.get("value") for p in nodes[n.path].iter("param")}
        assert (params["switch_node"], params["switch_agent"], params["switch_nodes"]) == (
            str(n.index), str(n.agent), str(len(wiring.nodes)))
        assert params["switch_control"] == str(n.control).lower()
        assert params["switch_coordinator"] == str(n.coordinator).lower()
        received = sorted(int(v) for k, v in params.items() if str(k).endswith("_switch_link"))
        assert received == sorted(n.receives)
        sent = sorted(int(item.partition(":")[0]) for k, v in params.items() if str(k).endswith("_switch_links")
                      for item in str(v).split())
        assert sent == sorted(n.sends)
    remaps = [r.get("to", "") for node in nodes.values() for r in node.iter("remap")]
    variable = [r for r in remaps if "__" in r]
    assert len(set(variable)) == len(variable) == len(wiring.links) == 4  # a topic per variable link
    assert len(remaps) - len(variable) == len(model.links) - len(wiring.links)  # the fixed links: as before
    msgs = {path.rpartition("/")[2] for path in files if path.endswith(".msg")}
    assert {"EarlSwitch.msg", "EarlSwitchAck.msg"} <= msgs


def test_a_model_without_configurations_gets_no_switch() -> None:
    files = render(load(ROOT / "samples" / "pick_and_place" / "pick_and_place.uml").model, "ros").generated
    assert not [path for path in files if "EarlSwitch" in path or path.endswith("switch_protocol.hpp")]
    assert not [path for path, content in files.items() if b"switch_node" in content or b"/earl/switch" in content]


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
@launched
def test_two_arm_launches_under_load_hand_every_command_over(
        two_arm: Path, core: tuple[Path, int, xmlrpc.client.ServerProxy],
        two_arm_switches: list[tuple[str, str]]) -> None:
    timeouts = switch_timeouts_ms(two_arm)
    failures: list[str] = []
    latencies: list[float] = []
    seconds: list[float] = []
    with cpu_hogs():
        for attempt in range(TWO_ARM_RUNS):
            lines, reached, took = launch(two_arm, core, TwoArm.finished)
            seconds.append(took)
            latencies += latencies_ms(lines)
            found = two_arm_problems(lines, reached, two_arm_switches, timeouts)
            if found:
                failures.append(f"launch {attempt + 1}: {found}\n{notable(lines)}")
    report("two_arm", latencies, seconds)
    assert not failures, f"{len(failures)} of {TWO_ARM_RUNS} launches failed:\n" + "\n".join(failures)


@pytest.mark.loaded
@launched
def test_two_arm_checks_catch_a_build_that_skips_the_drain(
        tmp_path_factory: pytest.TempPathFactory, core: tuple[Path, int, xmlrpc.client.ServerProxy],
        two_arm_switches: list[tuple[str, str]]) -> None:
    ws = undrained_built(tmp_path_factory.mktemp("two_arm_undrained_ws"))
    timeouts = switch_timeouts_ms(ws)
    caught = None
    with cpu_hogs():
        for attempt in range(catch_runs(TWO_ARM_CAMPAIGN)):
            lines, reached, _ = launch(ws, core, TwoArm.finished)
            found = two_arm_problems(lines, reached, two_arm_switches, timeouts)
            if found:
                caught = f"launch {attempt + 1}: {found}"
                break
    print(f"\ntwo_arm without the drain: {caught}")
    assert caught is not None, (f"all {catch_runs(TWO_ARM_CAMPAIGN)} launches of the drain-skipping build "
                                "passed the checks")


@launched
def test_forced_switches_name_every_command_they_lose(
        tmp_path_factory: pytest.TempPathFactory, core: tuple[Path, int, xmlrpc.client.ServerProxy]) -> None:
    """two_arm with switchTimeout = 0.001: the switches are forced, and every command is taken
    or named undelivered by the manipulator's node (the one it had taken and not yet processed
    too), the coordinator's counts adding up."""
    lines, reached, _ = launch(forced_built(tmp_path_factory.mktemp("two_arm_forced")), core, TwoArm.finished)
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
    """The sample's checks (``Harmoniser.problems``), the switchTimeouts the generated launch
    files give, and the C++ run's switch sequence."""
    found = undelivered(lines) + beyond_timeout(lines, timeouts)
    if not reached:
        return [*found, f"the run did not come back to guiding: switches {switches(lines)}"]
    if switches(lines) != expected:
        found.append(f"switches {switches(lines)} are not the C++ run's")
    return found + [problem for problem in Harmoniser.problems(lines) if problem not in found]


@pytest.mark.loaded
@launched
def test_harmoniser_launches_under_load_resume_the_guide_agent(
        harmoniser: Path, core: tuple[Path, int, xmlrpc.client.ServerProxy],
        tmp_path_factory: pytest.TempPathFactory) -> None:
    trace = cpp_trace(HARMONISER, tmp_path_factory.mktemp("harmoniser_cpp"), "Harmoniser_system", 230)
    expected = switches(trace)
    assert expected == Harmoniser.SWITCHES
    timeouts = switch_timeouts_ms(harmoniser)
    failures: list[str] = []
    latencies: list[float] = []
    seconds: list[float] = []
    with cpu_hogs():
        for attempt in range(HARMONISER_RUNS):
            lines, reached, took = launch(harmoniser, core, back_in_guiding)
            seconds.append(took)
            latencies += latencies_ms(lines)
            found = harmoniser_problems(lines, reached, expected, timeouts)
            if found:
                failures.append(f"launch {attempt + 1}: {found}\n{notable(lines)}")
    report("harmoniser", latencies, seconds)
    assert not failures, f"{len(failures)} of {HARMONISER_RUNS} launches failed:\n" + "\n".join(failures)


@launched
def test_a_restarted_guide_agent_starts_from_the_initial_state_and_fails_the_checks(
        tmp_path_factory: pytest.TempPathFactory, core: tuple[Path, int, xmlrpc.client.ServerProxy]) -> None:
    ws = restarted_built(tmp_path_factory.mktemp("harmoniser_restarted"))
    lines, reached, _ = launch(ws, core, back_in_guiding)
    assert reached and switches(lines) == Harmoniser.SWITCHES and not undelivered(lines)
    assert Harmoniser.first_waypoint_back(lines) == 1
    assert any(Harmoniser.GUIDE_START.match(line) for line in lines[Harmoniser.resumed_at(lines)[1]:])
    with pytest.raises(AssertionError):
        Harmoniser.assert_resumed(lines)

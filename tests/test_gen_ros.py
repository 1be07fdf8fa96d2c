"""The ROS 1 target: the sample's catkin packages (with its shipped user code) build with
catkin_make, the remaps of the launch files are exactly the model's links, and the launched
system runs the model: manip/a.cs goes idle -> jointMove -> idle -> emergencyStop."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
import xmlrpc.client
from collections.abc import Callable
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import GenError, render
from tests.support import known_bad
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs, run_until
from tests.support.ros_launch import (
    catkin_make,
    clear_start_barrier,
    environment,
    needs_catkin,
    needs_roslaunch,
    roscore,
    run,
)

ROOT = Path(__file__).resolve().parents[1]

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
USER = SAMPLE.parent / "user"
STATE = re.compile(r"^step \d+ manip/a\.cs: (?:start in (\w+)|(\w+) -> (\w+) \([^)]*\))$")
SEQUENCE = ["idle", "jointMove", "idle", "emergencyStop"]
CAMPAIGN = "ros pick_and_place"  # tests/support/campaigns.toml
LOADED_RUNS = loaded_runs(CAMPAIGN)
LAUNCH_TIMEOUT = 60.0  # s per launch: start-up of the 17 nodes under load, then about 1 s of script

@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """(a catkin workspace whose src/ is gen's output, gen's output): the sample's user code
    copied into src/user/ first."""
    ws = tmp_path_factory.mktemp("ros_ws")
    src = ws / "src"
    shutil.copytree(USER, src / "user")
    gen = run(sys.executable, "-m", "earl_m2t", "gen", SAMPLE, "--target", "ros", "-o", src)
    return ws, gen


@pytest.fixture(scope="module")
def built(workspace: tuple[Path, str]) -> Path:
    ws, _ = workspace
    return catkin_make(ws)


def launch_remaps(src: Path) -> dict[str, str]:
    """Every remap of every agent's launch file: input topic -> output topic."""
    remaps: dict[str, str] = {}
    for launch in sorted(src.glob("*/launch/*.launch")):
        for node in ElementTree.parse(launch).getroot().iter("node"):
            for remap in node.iter("remap"):
                assert remap.get("from") not in remaps
                remaps[remap.get("from", "")] = remap.get("to", "")
    return remaps


def snake(name: str) -> str:
    """A sample name in snake_case: motorController3/ve -> motor_controller3_ve."""
    return re.sub(r"\W+", "_", re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name)).lower()


def topic(buffer_path: str) -> str:
    """The documented topic of a buffer: /<agent>/<subsystem>/<buffer>, each in snake_case."""
    subsystem_path, _, buffer = buffer_path.rpartition(".")
    agent, _, subsystem = subsystem_path.partition(".")
    return "/" + "/".join(snake(part) for part in (agent, subsystem, buffer))


def test_gen_writes_a_package_per_agent_the_messages_and_the_bringup(workspace: tuple[Path, str]) -> None:
    ws, gen = workspace
    packages = sorted(p.parent.name for p in (ws / "src").glob("*/package.xml"))
    assert packages == ["pick_and_place_bringup", "pick_and_place_grip_a", "pick_and_place_manip_a",
                        "pick_and_place_msgs", "pick_and_place_task_a"]
    for package in packages:
        assert ElementTree.parse(ws / "src" / package / "package.xml").getroot().get("format") == "3"
    assert (ws / "src" / "pick_and_place_msgs" / "msg" / "ManipulatorCommand.msg").is_file()
    assert (ws / "src" / "pick_and_place_bringup" / "launch" / "system.launch").is_file()
    kept = [line for line in gen.splitlines() if line.startswith("kept ")]
    assert len(kept) == 14 and not [line for line in gen.splitlines() if line.startswith(("created ", "orphaned "))]


def test_the_remaps_of_the_launch_files_are_exactly_the_links_of_the_model(workspace: tuple[Path, str]) -> None:
    ws, _ = workspace
    model = load(str(SAMPLE)).model
    links = {topic(link.target): topic(link.source) for link in model.links}
    assert len(links) == len(model.links) == 32
    assert launch_remaps(ws / "src") == links


def test_every_subsystem_instance_is_a_node_of_its_agents_launch_file(workspace: tuple[Path, str]) -> None:
    ws, _ = workspace
    model = load(str(SAMPLE)).model
    names = set()
    for launch in (ws / "src").glob("*/launch/*.launch"):
        for node in ElementTree.parse(launch).getroot().iter("node"):
            params = {p.get("name"): p.get("value") for p in node.iter("param")}
            assert params["period"] == "$(arg period)"
            names.add(params["path"])
    assert names == {sub.path for sub in model.subsystems}


def test_packages_nodes_and_topics_are_snake_case_and_messages_camel_case(workspace: tuple[Path, str]) -> None:
    ws, _ = workspace
    snake_name = re.compile(r"^[a-z][a-z0-9_]*$")
    assert all(snake_name.match(p.parent.name) for p in (ws / "src").glob("*/package.xml"))
    assert all(re.match(r"^[A-Z][A-Za-z0-9]*$", m.stem) for m in (ws / "src").glob("*/msg/*.msg"))
    for launch in sorted((ws / "src").glob("*/launch/*.launch")):
        root = ElementTree.parse(launch).getroot()
        for node in root.iter("node"):
            assert all(snake_name.match(node.get(key, "")) for key in ("name", "ns", "type", "pkg")), node.attrib
            for remap in node.iter("remap"):
                for name in (remap.get("from", ""), remap.get("to", "")):
                    assert name.startswith("/") and all(snake_name.match(part) for part in name[1:].split("/")), name
            for param in node.iter("param"):
                assert snake_name.match(param.get("name", "")), param.attrib


def test_names_that_collide_as_ros_names_are_refused_or_forced_apart(tmp_path: Path) -> None:
    # manipulator_state/ib and manipulatorState/ib are distinct C++ identifiers, one ROS topic
    text = SAMPLE.read_text(encoding="utf-8").replace("gripperStatus/ib", "manipulator_state/ib")
    model = tmp_path / "model.uml"
    model.write_text(text, encoding="utf-8")
    shutil.copy(SAMPLE.parent / "EARL.profile.uml", tmp_path / "EARL.profile.uml")
    refused = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "ros", "-o",
                              str(tmp_path / "out")], capture_output=True, text=True, timeout=120)
    assert refused.returncode != 0 and not (tmp_path / "out").exists()
    # the check finds it first (D004), at the second buffer ...
    assert refused.stderr.splitlines()[0].endswith(
        "D004 error: task/a.cs.manipulator_state/ib: 'manipulatorState/ib' and 'manipulator_state/ib' map to the "
        "same ROS name 'manipulator_state_ib' [task/a.cs.manipulator_state/ib]")
    # ... and the generator refuses it too when asked without the check
    with pytest.raises(GenError) as refusal:
        render(load(model).model, "ros")
    assert str(refusal.value) == (
        "D004 task/a.cs.manipulator_state/ib: 'manipulator_state/ib' and 'manipulatorState/ib' both "
        "map to the ROS topic 'manipulator_state_ib' (--force: 'manipulator_state_ib_2')")
    run(sys.executable, "-m", "earl_m2t", "gen", model, "--target", "ros", "--force", "-o", tmp_path / "out")
    remaps = launch_remaps(tmp_path / "out")
    assert remaps["/task_a/cs/manipulator_state_ib"] == "/manip_a/cs/manipulator_state_ob"
    assert remaps["/task_a/cs/manipulator_state_ib_2"] == "/grip_a/cs/gripper_status_ob"



def test_agents_named_after_the_generated_packages_get_packages_of_their_own(tmp_path: Path) -> None:
    """Agents named ``msgs`` and ``bringup`` would take the names of the message and bringup
    packages: check passes such a model, so the ros and ros2 targets generate it, the agents'
    packages with the suffix ``_agent``."""
    text = SAMPLE.with_suffix(".sysml").read_text(encoding="utf-8")
    model = tmp_path / "model.sysml"
    model.write_text(text.replace("'task/a'", "'msgs'").replace("'grip/a'", "'bringup'"), encoding="utf-8")
    run(sys.executable, "-m", "earl_m2t", "check", model)
    for target in ("ros", "ros2"):
        run(sys.executable, "-m", "earl_m2t", "gen", model, "--target", target, "-o", tmp_path / target)
        packages = sorted(p.parent.name for p in (tmp_path / target).glob("*/package.xml"))
        assert packages == ["pick_and_place_bringup", "pick_and_place_bringup_agent", "pick_and_place_manip_a",
                            "pick_and_place_msgs", "pick_and_place_msgs_agent"], (target, packages)

@needs_catkin
def test_catkin_make_builds_the_messages_and_one_node_per_subsystem_definition(built: Path) -> None:
    nodes = sorted(p.relative_to(built / "devel" / "lib").as_posix()
                   for p in (built / "devel" / "lib").glob("*/*_node"))
    assert nodes == ["pick_and_place_grip_a/cs_node", "pick_and_place_grip_a/finger_controller_ve_node",
                     "pick_and_place_grip_a/finger_motor_re_node", "pick_and_place_manip_a/cs_node",
                     "pick_and_place_manip_a/motor_controller_k_ve_node", "pick_and_place_manip_a/motor_k_re_node",
                     "pick_and_place_task_a/cs_node"]
    assert (built / "devel" / "include" / "pick_and_place_msgs" / "ManipulatorCommand.h").is_file()


def manip_states(lines: list[str]) -> list[str]:
    """The states manip/a.cs entered, in order, from the nodes' output."""
    return [m.group(1) or m.group(3) for m in map(STATE.match, (line.strip() for line in lines)) if m]


def missed_sequence(env: dict[str, str], master: xmlrpc.client.ServerProxy,
                    seen: Callable[[list[str]], bool] | None = None) -> str | None:
    """One launch at 1 ms, stopped as soon as manip/a.cs reached emergencyStop (or ``seen``
    held): what went wrong, or None when it went through SEQUENCE."""
    clear_start_barrier(master)
    lines, reached = run_until(["roslaunch", "--wait", "pick_and_place_bringup", "system.launch", "period:=0.001"],
                               seen or (lambda out: "emergencyStop" in manip_states(out)), LAUNCH_TIMEOUT, env)
    if reached and manip_states(lines)[:4] == SEQUENCE:
        return None
    return f"{manip_states(lines)}\n" + "\n".join(lines[-40:])


@pytest.mark.loaded
@needs_catkin
@needs_roslaunch
def test_the_launched_system_takes_manip_cs_through_the_states_of_the_model(built: Path, tmp_path: Path) -> None:
    """Launches at 1 ms periods with one busy process per CPU: task/a.cs sends its setpoint
    in one period only, and manip/a.cs, activated by each command it queues, never loses it.
    Each run stops as soon as manip/a.cs reached emergencyStop (the script needs about 0.85 s
    at 1 ms); one roscore serves all runs, its start barrier cleared between them."""
    failures = []
    with roscore(tmp_path) as (port, master), cpu_hogs():
        env = {**environment(built, tmp_path, port), "PICK_AND_PLACE_QUIET": "1"}
        for attempt in range(1, LOADED_RUNS + 1):
            missed = missed_sequence(env, master)
            if missed:
                failures.append(f"run {attempt}: {missed}")
    assert not failures, f"{len(failures)} of {LOADED_RUNS} launches missed the sequence:\n" + "\n".join(failures[:3])


def latest_value_built(folder: Path) -> Path:
    """The known-bad variant's workspace (tests/support/known_bad.py), built (once per content:
    tests/test_campaign_builds.py builds it among the parallel tests)."""
    ws = folder / "ws"
    shutil.copytree(USER, ws / "src" / "user")
    run(sys.executable, "-m", "earl_m2t", "gen", known_bad.one_shot_into_latest_value(folder / "model"),
        "--target", "ros", "-o", ws / "src")
    return catkin_make(ws)


@pytest.mark.loaded
@needs_catkin
@needs_roslaunch
def test_the_launch_checks_catch_a_one_shot_command_into_a_latest_value_input(tmp_path: Path) -> None:
    """The known-bad variant (tests/support/known_bad.py): manip/a.cs's commands a latest-value
    input and manip/a.cs on its own clock. Launched under load, a later command overwrites the
    setpoint before manip/a.cs reads it in one of the launches the campaign keeps."""
    built = latest_value_built(tmp_path)
    with roscore(tmp_path) as (port, master), cpu_hogs():
        env = {**environment(built, tmp_path, port), "PICK_AND_PLACE_QUIET": "1"}
        caught = next((attempt for attempt in range(1, catch_runs(CAMPAIGN) + 1)
                       if missed_sequence(env, master, known_bad.SetpointWatch(manip_states))), None)
    print(f"\nros latest-value variant: caught in launch {caught}")
    assert caught is not None, f"all {catch_runs(CAMPAIGN)} launches of the latest-value variant reached the sequence"

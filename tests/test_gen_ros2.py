"""The ROS 2 target: the sample's ament_cmake packages (with its shipped user code), generated the
same on every run, whose launch file remaps exactly the model's links with the QoS of each
receive mode; against a real ROS 2 Jazzy (tests/support/ros2.py) the messages pass rosidl's own
parser, `colcon build` builds the workspace, and `ros2 launch` runs the model, composed and as
separate processes, its managed nodes configured then activated by the generated manager:
manip/a.cs goes idle -> jointMove -> idle -> emergencyStop."""

from __future__ import annotations

import ast
import json
import random
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from collections.abc import Callable
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.targets.ros2 import yaml_scalar
from tests.support import known_bad, ros2
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs, run_until

ROOT = Path(__file__).resolve().parents[1]
# the ROS 2 modules share one worker of a parallel run: two launches at once could meet on a ROS domain
pytestmark = pytest.mark.xdist_group("ros2")

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
USER = SAMPLE.parent / "user"
# launch prefixes each line of a process with "[<process>] "
STATE = re.compile(r"^(?:\[[^\]]+\] )?step \d+ manip/a\.cs: (?:start in (\w+)|(\w+) -> (\w+) \([^)]*\))$")
SEQUENCE = ["idle", "jointMove", "idle", "emergencyStop"]
BRINGUP = "pick_and_place_bringup"
PACKAGES = ["pick_and_place_bringup", "pick_and_place_grip_a", "pick_and_place_manip_a", "pick_and_place_msgs",
            "pick_and_place_task_a"]
LAUNCH_TIMEOUT = 90.0  # s: start-up of 3 containers (or 17 processes) and the barrier, then about 1 s of script
# the loaded campaigns (tests/support/campaigns.toml), composed or a process per node
CAMPAIGNS = {"true": "ros2 pick_and_place", "false": "ros2 pick_and_place processes"}
OVERFLOW = re.compile(r"overflowed, (\d+) value\(s\) lost")
DIED = re.compile(r"\[ERROR\] \[([\w-]+)\]: process has died")


def gen(out: Path, *flags: str) -> str:
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(SAMPLE), "--target", "ros2", "-o", str(out),
                             *flags], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return result.stdout


def sample_workspace(ws: Path) -> str:
    """Makes ``ws`` a colcon workspace whose src/ is gen's output, the sample's user code copied
    into src/user/ first; gen's output."""
    shutil.copytree(USER, ws / "src" / "user")
    return gen(ws / "src")


def sample_built(jazzy: ros2.Installation, ws: Path) -> Path:
    """The sample's workspace built, once per content: tests/test_campaign_builds.py builds it
    among the parallel tests."""
    sample_workspace(ws)
    return jazzy.colcon_build(ws)


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """(a colcon workspace whose src/ is gen's output, gen's output)."""
    ws = tmp_path_factory.mktemp("ros2_ws")
    return ws, sample_workspace(ws)


def launch_agents(src: Path) -> list[tuple[str, str, str, list[tuple[str, str, str, str, list[tuple[str, str]]]]]]:
    """The AGENTS table of the generated launch file, read without importing launch: (namespace,
    container, parameter file, [(package, plugin, executable, node, remappings)])."""
    tree = ast.parse((src / BRINGUP / "launch" / "system.launch.py").read_text())
    value = next(node.value for node in tree.body if isinstance(node, ast.Assign)
                 and any(isinstance(t, ast.Name) and t.id == "AGENTS" for t in node.targets))
    return ast.literal_eval(value)


def node_parameters(bringup: Path) -> dict[str, dict[str, object]]:
    """The values of every agent's parameter file under ``bringup`` (its source or installed share), by node."""
    return {node: values for path in sorted((bringup / "config").glob("*.yaml"))
            for node, values in ros2.generated_parameters(path).items()}


def snake(name: str) -> str:
    """A sample name in snake_case: motorController3/ve -> motor_controller3_ve."""
    return re.sub(r"\W+", "_", re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", name)).lower()


def topic(buffer_path: str) -> str:
    """The documented topic of a buffer: /<agent>/<subsystem>/<buffer>, each in snake_case."""
    subsystem_path, _, buffer = buffer_path.rpartition(".")
    agent, _, subsystem = subsystem_path.partition(".")
    return "/" + "/".join(snake(part) for part in (agent, subsystem, buffer))


def test_gen_writes_an_ament_package_per_agent_the_messages_and_the_bringup(workspace: tuple[Path, str]) -> None:
    ws, output = workspace
    src = ws / "src"
    assert sorted(p.parent.name for p in src.glob("*/package.xml")) == PACKAGES
    for package in PACKAGES:
        root = ElementTree.parse(src / package / "package.xml").getroot()
        assert root.get("format") == "3" and root.findtext("export/build_type") == "ament_cmake"
    assert "rosidl_generate_interfaces(" in (src / "pick_and_place_msgs" / "CMakeLists.txt").read_text()
    manip = (src / "pick_and_place_manip_a" / "CMakeLists.txt").read_text()
    assert re.findall(r"rclcpp_components_register_node\(\S+ PLUGIN \"([\w:]+)\" EXECUTABLE (\w+)\)", manip) == [
        ("pick_and_place_manip_a::Cs", "cs_node"), ("pick_and_place_manip_a::MotorControllerKVe",
                                                    "motor_controller_k_ve_node"),
        ("pick_and_place_manip_a::MotorKRe", "motor_k_re_node")]
    kept = [line for line in output.splitlines() if line.startswith("kept ")]
    assert len(kept) == 14 and not [line for line in output.splitlines() if line.startswith(("created ", "orphaned "))]


def test_generation_is_deterministic_and_keeps_user_code(tmp_path: Path) -> None:
    first, second = tmp_path / "a" / "out", tmp_path / "b" / "out"
    gen(first)
    gen(second)
    files = sorted(p.relative_to(first).as_posix() for p in first.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(second).as_posix() for p in second.rglob("*") if p.is_file())
    assert all((first / f).read_bytes() == (second / f).read_bytes() for f in files)
    user_file = first / "user" / "manip_a" / "cs" / "jointMove_pf.hpp"
    user_file.write_text("// mine\n")
    again = gen(first)
    assert user_file.read_text() == "// mine\n" and "created " not in again


def test_the_remaps_of_the_launch_file_are_exactly_the_links_of_the_model(workspace: tuple[Path, str]) -> None:
    ws, _ = workspace
    model = load(str(SAMPLE)).model
    parameters = node_parameters(ws / "src" / BRINGUP)
    remaps: dict[str, str] = {}
    paths = set()
    for namespace, _, _, nodes in launch_agents(ws / "src"):
        for _, _, _, name, remappings in nodes:
            paths.add(parameters[f"/{namespace}/{name}"]["path"])
            for source, target in remappings:
                assert source.startswith(f"/{namespace}/{name}/") and source not in remaps
                remaps[source] = target
    assert len(model.links) == 32
    assert remaps == {topic(link.target): topic(link.source) for link in model.links}
    assert paths == {sub.path for sub in model.subsystems}


def test_each_agent_has_a_parameter_file_with_the_values_of_its_nodes(workspace: tuple[Path, str]) -> None:
    """config/<agent>.yaml of the bringup, named by the launch file's AGENTS: under each node's
    fully qualified name its path, the defaults of [node] in target.toml, the size of the
    system and a link count per buffer, in sorted order."""
    ws, _ = workspace
    bringup = ws / "src" / BRINGUP
    model = load(str(SAMPLE)).model
    agents = launch_agents(ws / "src")
    assert [(namespace, parameter_file) for namespace, _, parameter_file, _ in agents] == [
        (namespace, f"config/{namespace}.yaml") for namespace in ("manip_a", "grip_a", "task_a")]
    for namespace, _, parameter_file, nodes in agents:
        values = ros2.generated_parameters(bringup / parameter_file)
        assert list(values) == [f"/{namespace}/{node[3]}" for node in nodes]
        for node in values.values():
            assert list(node) == sorted(node)
            assert {k: node[k] for k in ("period", "non_finite", "quiet", "expected_nodes", "connect_timeout")} == {
                "period": 0.01, "non_finite": "error", "quiet": False, "expected_nodes": 17, "connect_timeout": 10.0}
    by_path = {values["path"]: values for values in node_parameters(bringup).values()}
    assert sorted(by_path) == sorted(sub.path for sub in model.subsystems)
    cs = by_path["manip/a.cs"]
    assert cs["manipulator_command_ib_links"] == 1 and cs["motor_controller_state6_ib_links"] == 1
    installs = (bringup / "CMakeLists.txt").read_text()
    for _, _, parameter_file, _ in agents:
        assert f"install(FILES {parameter_file} DESTINATION share/${{PROJECT_NAME}}/config)" in installs


def test_a_parameter_value_is_a_yaml_scalar_of_its_own_type() -> None:
    """Strings double-quoted with YAML's escapes, floats with a point (PyYAML reads 1e-06 as a string)."""
    assert [yaml_scalar(v) for v in (True, 17, 10.0, 1e-06, 2.5e20)] == ["true", "17", "10.0", "1.0e-06", "2.5e+20"]
    assert yaml_scalar("true") == '"true"' and yaml_scalar("manip/a.cs") == '"manip/a.cs"'
    assert yaml_scalar('a"b\\c\td\x85e\u2028é') == '"a\\"b\\\\c\\td\\u0085e\\u2028é"'
    with pytest.raises(GenError):
        yaml_scalar(float("nan"))


def test_qos_follows_the_receive_modes(workspace: tuple[Path, str]) -> None:
    """manip/a.cs queues its commands (reliable, keep all; task/a.cs publishes them so) and
    keeps the latest value of every other input (reliable, transient local, depth 1)."""
    ws, _ = workspace
    src = ws / "src"

    def qos_of(source: Path) -> dict[str, str]:
        found = re.findall(r'"~/(\w+)", (rclcpp::QoS\([^;]*?\)\.\w+\(\)\.\w+\(\))', source.read_text())
        return dict(found)

    manip = qos_of(src / "pick_and_place_manip_a" / "src" / "cs_component.cpp")
    latest = "rclcpp::QoS(rclcpp::KeepLast(1)).reliable().transient_local()"
    queue = "rclcpp::QoS(rclcpp::KeepAll()).reliable().durability_volatile()"
    assert manip["manipulator_command_ib"] == queue
    assert {t: q for t, q in manip.items() if t.endswith("_ib") and t != "manipulator_command_ib"} == {
        f"motor_controller_state{k}_ib": latest for k in range(1, 7)}
    assert qos_of(src / "pick_and_place_task_a" / "src" / "cs_component.cpp")["manipulator_command_ob"] == queue


# ---------------------------------------------------------------- against a real ROS 2 Jazzy


@pytest.fixture(scope="module")
def jazzy() -> ros2.Installation:
    """The ROS 2 prefix of tests/support/ros2.py. With ../shared/vendor/ros2 beside the checkout
    a missing or failed build is a failure (never a skip), with the build log's tail."""
    return ros2.installation_for_tests()


PARSE = """
import json, sys
from rosidl_adapter.parser import parse_message_file
out = {}
for path in sys.argv[2:]:
    message = parse_message_file(sys.argv[1], path)
    out[message.msg_name] = [[str(f.type), f.name, sorted(f.annotations)] for f in message.fields]
print(json.dumps(out))
"""


def test_rosidl_parses_every_generated_message(workspace: tuple[Path, str], jazzy: ros2.Installation) -> None:
    ws, _ = workspace
    messages = sorted((ws / "src" / "pick_and_place_msgs" / "msg").glob("*.msg"))
    result = subprocess.run([str(jazzy.python), "-c", PARSE, "pick_and_place_msgs", *map(str, messages)],
                            capture_output=True, text=True, env=jazzy.environment(), timeout=120)
    assert result.returncode == 0, result.stderr
    parsed = json.loads(result.stdout)
    assert sorted(parsed) == sorted(m.stem for m in messages)
    # a comment is only a comment: rosidl reads no unit (a bracket) nor other annotation in it
    assert {name for fields in parsed.values() for _, _, annotations in fields for name in annotations} == {"comment"}
    assert parsed["ManipulatorCommand"][0][:2] == ["pick_and_place_msgs/JointPosition[<=1]", "joint_pos_setpoint"]
    assert parsed["JointPosition"] == [["float64[6]", "q", ["comment"]]]


@pytest.fixture(scope="module")
def built(workspace: tuple[Path, str], jazzy: ros2.Installation) -> Path:
    ws, _ = workspace
    return jazzy.colcon_build(ws)


def test_colcon_builds_a_component_library_per_agent_and_an_executable_per_definition(built: Path) -> None:
    install = built / "install"
    for agent in ("grip_a", "manip_a", "task_a"):
        assert (install / f"pick_and_place_{agent}" / "lib" / f"libpick_and_place_{agent}_components.so").is_file()
    executables = sorted(p.relative_to(install).as_posix() for p in install.glob("*/lib/*/*_node"))
    assert executables == [
        "pick_and_place_grip_a/lib/pick_and_place_grip_a/cs_node",
        "pick_and_place_grip_a/lib/pick_and_place_grip_a/finger_controller_ve_node",
        "pick_and_place_grip_a/lib/pick_and_place_grip_a/finger_motor_re_node",
        "pick_and_place_manip_a/lib/pick_and_place_manip_a/cs_node",
        "pick_and_place_manip_a/lib/pick_and_place_manip_a/motor_controller_k_ve_node",
        "pick_and_place_manip_a/lib/pick_and_place_manip_a/motor_k_re_node",
        "pick_and_place_task_a/lib/pick_and_place_task_a/cs_node"]
    assert (install / "pick_and_place_msgs" / "include" / "pick_and_place_msgs" / "pick_and_place_msgs" / "msg"
            / "manipulator_command.hpp").is_file()


def manip_states(lines: list[str]) -> list[str]:
    """The states manip/a.cs entered, in order, from the launch's output."""
    return [m.group(1) or m.group(3) for m in map(STATE.match, (line.strip() for line in lines)) if m]


def launch_once(built: Path, env: dict[str, str], composed: str,
                seen: Callable[[list[str]], bool] | None = None) -> tuple[str | None, int]:
    """One launch at 1 ms on a ROS domain of its own, stopped as soon as manip/a.cs reached
    emergencyStop (or ``seen`` held): (what went wrong, or None when it went through SEQUENCE
    with every node activated; the streamed commands its queue reported lost)."""
    env["ROS_DOMAIN_ID"] = str(random.randint(1, 100))
    lines, reached = run_until(["ros2", "launch", "pick_and_place_bringup", "system.launch.py",
                                "period:=0.001", f"composed:={composed}"],
                               seen or (lambda out: "emergencyStop" in manip_states(out)), LAUNCH_TIMEOUT, env)
    lost = sum(int(m.group(1)) for m in map(OVERFLOW.search, lines) if m)
    activated = any(line.endswith("[earl_lifecycle_manager]: activated: 17 nodes") for line in lines)
    if reached and manip_states(lines)[:4] == SEQUENCE and activated:
        return None, lost
    # what the nodes said of manip/a.cs, and everything a process that died wrote
    died = {m.group(1) for m in map(DIED.search, lines) if m}
    notable = [line for line in lines if re.search(r"a\.cs: |WARN|ERROR|died|manager", line)
               or any(line.startswith(f"[{process}] ") for process in died)]
    return f"{manip_states(lines)}\n" + "\n".join(notable[:80] + ["..."] + lines[-30:]), lost


def launch_environment(built: Path, jazzy: ros2.Installation, folder: Path) -> dict[str, str]:
    env = jazzy.environment(built)
    env.update(ROS_LOG_DIR=str(folder / "log"), ROS_HOME=str(folder / "home"), PICK_AND_PLACE_QUIET="1")
    return env


# Each under a CPU hog per core at 1 ms periods, composed (3 containers) or a process per node
# (17 processes, each launch tens of seconds on 2 loaded cores): two campaigns.
@pytest.mark.loaded
@pytest.mark.parametrize("composed", ["true", "false"])
def test_launches_under_load_take_manip_cs_through_the_states_of_the_model(
        built: Path, jazzy: ros2.Installation, tmp_path: Path, composed: str) -> None:
    """Each launch on a ROS domain of its own, stopped as soon as manip/a.cs reached
    emergencyStop. task/a.cs sends its jointMove setpoint in one command only, over a queued
    link (reliable, keep all): idle -> jointMove in every run is that one-shot command arriving.
    The streamed commands its queue lost when full (reported, never silent) are counted."""
    runs = loaded_runs(CAMPAIGNS[composed])
    env = launch_environment(built, jazzy, tmp_path)
    failures: list[str] = []
    lost = 0
    with cpu_hogs():
        for attempt in range(1, runs + 1):
            failed, overflowed = launch_once(built, env, composed)
            lost += overflowed
            if failed:
                failures.append(f"run {attempt}: {failed}")
    print(f"\nros2 launches, composed={composed}, period 1 ms, under load: {runs - len(failures)} of "
          f"{runs} completed the sequence (the one-shot setpoint arrived); {lost} streamed command(s) "
          f"lost in reported overflows")
    assert not failures, f"{len(failures)} of {runs} launches failed:\n" + "\n".join(failures[:2])


def latest_value_built(jazzy: ros2.Installation, folder: Path) -> Path:
    """The known-bad variant's workspace (tests/support/known_bad.py), built (once per content:
    tests/test_campaign_builds.py builds it among the parallel tests)."""
    ws = folder / "ws"
    shutil.copytree(USER, ws / "src" / "user")
    model = known_bad.one_shot_into_latest_value(folder / "model")
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "ros2", "-o",
                             str(ws / "src")], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return jazzy.colcon_build(ws)


@pytest.mark.loaded
@pytest.mark.parametrize("composed", ["true", "false"])
def test_the_launch_checks_catch_a_one_shot_command_into_a_latest_value_input(
        jazzy: ros2.Installation, tmp_path: Path, composed: str) -> None:
    """The known-bad variant (tests/support/known_bad.py): manip/a.cs's commands a latest-value
    link (reliable, transient local, depth 1) and manip/a.cs on its own clock. Launched under
    load, a later command overwrites the setpoint before manip/a.cs reads it in one of the
    launches the campaign keeps."""
    built = latest_value_built(jazzy, tmp_path)
    env = launch_environment(built, jazzy, tmp_path)
    runs = catch_runs(CAMPAIGNS[composed])
    with cpu_hogs():
        caught = next((attempt for attempt in range(1, runs + 1)
                       if launch_once(built, env, composed, known_bad.SetpointWatch(manip_states))[0]), None)
    print(f"\nros2 latest-value variant, composed={composed}: caught in launch {caught}")
    assert caught is not None, f"all {runs} launches of the latest-value variant reached the sequence"


def test_a_parameter_outside_its_declared_range_is_refused(built: Path, jazzy: ros2.Installation) -> None:
    """Every node declares its parameters with ranges (transforms/ros2/target.toml): rclcpp refuses
    a negative period, and the node does not start; a value inside runs."""
    node = built / "install" / "pick_and_place_manip_a" / "lib" / "pick_and_place_manip_a" / "cs_node"
    env = jazzy.environment(built, domain_id=random.randint(101, 200))
    for parameter, kind in (("period:=-1.0", "floating point"), ("expected_nodes:=-3", "integer")):
        result = subprocess.run([str(node), "--ros-args", "-p", parameter], capture_output=True, text=True, env=env,
                                timeout=60)
        assert result.returncode != 0
        assert f"doesn't comply with {kind} range" in result.stdout + result.stderr, result.stderr
    with pytest.raises(subprocess.TimeoutExpired):  # inside its range: it starts and keeps running
        subprocess.run([str(node), "--ros-args", "-p", "period:=0.5"], capture_output=True, env=env, timeout=3)


def installed_parameter_file(built: Path, agent: str) -> Path:
    return built / "install" / BRINGUP / "share" / BRINGUP / "config" / f"{agent}.yaml"


def edited_parameter_file(built: Path, tmp_path: Path, old: str, new: str) -> Path:
    """A copy of manip/a's installed parameter file with the line ``old`` of every node made ``new``."""
    text = installed_parameter_file(built, "manip_a").read_text()
    assert f"\n    {old}\n" in text
    edited = tmp_path / "manip_a.yaml"
    edited.write_text(text.replace(f"\n    {old}\n", f"\n    {new}\n"))
    return edited


def test_a_value_outside_its_range_in_the_parameter_file_is_refused(built: Path, jazzy: ros2.Installation,
                                                                     tmp_path: Path) -> None:
    """rclcpp checks the values of a parameter file against the declared ranges too: manip/a.cs
    given its agent's file with a negative period does not start."""
    node = built / "install" / "pick_and_place_manip_a" / "lib" / "pick_and_place_manip_a" / "cs_node"
    edited = edited_parameter_file(built, tmp_path, "period: 0.01", "period: -1.0")
    env = jazzy.environment(built, domain_id=random.randint(101, 200))
    result = subprocess.run([str(node), "--ros-args", "-r", "__ns:=/manip_a", "--params-file", str(edited)],
                            capture_output=True, text=True, env=env, timeout=60)
    assert result.returncode != 0
    assert "doesn't comply with floating point range" in result.stdout + result.stderr, result.stderr


def test_a_value_of_the_parameter_file_is_the_one_the_node_uses(built: Path, jazzy: ros2.Installation,
                                                               tmp_path: Path) -> None:
    """manip/a.cs started alone waits connect_timeout for its links and the 16 other nodes
    (expected_nodes, from the file): 10 s with the installed file, no time at all with a copy
    that says 0, and it enters idle at once."""
    node = built / "install" / "pick_and_place_manip_a" / "lib" / "pick_and_place_manip_a" / "cs_node"
    edited = edited_parameter_file(built, tmp_path, "connect_timeout: 10.0", "connect_timeout: 0.0")
    env = jazzy.environment(built, domain_id=random.randint(101, 200))
    env.update(ROS_LOG_DIR=str(tmp_path / "log"), PICK_AND_PLACE_QUIET="1")
    lines, started = run_until([node, "--ros-args", "-r", "__ns:=/manip_a", "--params-file", str(edited),
                                "-p", "autostart:=true"], lambda out: manip_states(out)[:1] == ["idle"], 8.0, env)
    assert started, "\n".join(lines[-20:])


LAUNCH_NODES = 17 + 3 + 1  # the subsystems' nodes, 3 containers when composed, the lifecycle manager


def subsystem_nodes(nodes: list[dict[str, object]]) -> list[dict[str, object]]:
    return [n for n in nodes if n["package"] not in ("rclcpp_components", BRINGUP)]


def remap_problems(nodes: list[dict[str, object]], links: dict[str, str]) -> list[str]:
    """How the remappings launch gives the nodes differ from the model's links (input's topic ->
    output's topic), each remap in the namespace of its node."""
    problems = []
    remaps: dict[str, str] = {}
    for node in subsystem_nodes(nodes):
        for source, target in node["remappings"]:  # type: ignore[attr-defined]
            if not source.startswith(f"{node['name']}/") or source in remaps:
                problems.append(f"{node['name']}: remaps {source} again or from another node")
            remaps[source] = target
    problems += [f"link {s} -> {t} not remapped" for s, t in links.items() if remaps.get(s) != t]
    problems += [f"remap {s} -> {t} is no link" for s, t in remaps.items() if links.get(s) != t]
    return problems


@pytest.mark.parametrize("composed", ["true", "false"])
def test_launch_loads_the_launch_file_with_the_links_of_the_model_and_the_agents_parameter_files(
        built: Path, jazzy: ros2.Installation, tmp_path: Path, composed: str) -> None:
    """system.launch.py as launch's own loader evaluates it (tests/support/ros2_launch_description.py):
    the remaps are exactly the model's links, every subsystem is one node, which gets its agent's
    installed parameter file first and then period:= as an override (and no override without
    it), composed in its agent's container or a process of its own. A copy of the launch file
    without one remap is reported."""
    model = load(str(SAMPLE)).model
    links = {topic(link.target): topic(link.source) for link in model.links}
    share = built / "install" / BRINGUP / "share" / BRINGUP
    launch_file = share / "launch" / "system.launch.py"
    nodes = jazzy.launch_description(built, launch_file, composed=composed, period="0.002")
    assert len(nodes) == LAUNCH_NODES - (3 if composed == "false" else 0)
    assert remap_problems(nodes, links) == []
    parameters = node_parameters(share)
    paths = {values["path"]: name for name, values in parameters.items()}
    assert sorted(n["name"] for n in subsystem_nodes(nodes)) == sorted(paths.values())
    assert sorted(paths) == sorted(sub.path for sub in model.subsystems)
    for node in subsystem_nodes(nodes):
        agent = str(node["name"]).split("/")[1]
        assert node["parameters"] == [{"file": str(installed_parameter_file(built, agent))},
                                      {"values": {"period": 0.002}}], node
        assert node["container"] == (f"/{agent}/{agent}_container" if composed == "true" else None)
        if composed == "true":  # what launch_ros sends the container: the node's section of the file, then period
            assert node["loaded"] == {**parameters[str(node["name"])], "period": 0.002}
    unset = jazzy.launch_description(built, launch_file, composed=composed)
    assert all(len(n["parameters"]) == 1 for n in subsystem_nodes(unset))  # type: ignore[arg-type]

    # the comparison can fail: a copy of the launch file without the remap of manip/a.cs's commands
    remap = '("/manip_a/cs/manipulator_command_ib", "/task_a/cs/manipulator_command_ob")'
    text = launch_file.read_text()
    edited = tmp_path / "system.launch.py"
    edited.write_text(text.replace(", " + remap, "").replace(remap + ", ", ""))
    assert edited.read_text() != text
    assert remap_problems(jazzy.launch_description(built, edited, composed=composed), links) == [
        "link /manip_a/cs/manipulator_command_ib -> /task_a/cs/manipulator_command_ob not remapped"]


GRAPH = ROOT / "tests" / "support" / "ros2_graph.py"
# what discovery tells of a remote endpoint's QoS: reliability and durability (its history and
# depth stay local, "unknown" in the graph; test_qos_follows_the_receive_modes reads them)
LATEST_QOS = {"reliability": "reliable", "durability": "transient_local"}
QUEUE_QOS = {"reliability": "reliable", "durability": "volatile"}


def test_the_running_graph_subscribes_each_input_to_its_link_with_the_qos_of_its_receive_mode(
        built: Path, jazzy: ros2.Installation, tmp_path: Path) -> None:
    """The graph DDS reports while the composed system runs: each link's output topic has the
    linked input's node among its subscriptions, with the QoS of the input's receive mode, and
    its subscriber matched the output's publisher. A subscription of our own that asks a queued
    topic for the last value (transient local, which the publisher does not offer) is refused
    as incompatible: the check this test makes can fail."""
    model = load(str(SAMPLE)).model
    nodes = {values["path"]: node for node, values in node_parameters(built / "src" / BRINGUP).items()}
    inputs = {b.path: b for sub in model.subsystems for b in sub.inputs}
    expected: dict[str, list[tuple[str, dict[str, object]]]] = {}
    for link in model.links:
        receive = inputs[link.target].receive
        expected.setdefault(topic(link.source), []).append(
            (nodes[link.target.rpartition(".")[0]], QUEUE_QOS if receive == "queue" else LATEST_QOS))
    queued_topic = next(t for t, subs in expected.items() if subs[0][1] is QUEUE_QOS)
    request = {"topics": {t: [len(subs), 1] for t, subs in expected.items()}, "timeout": 30.0,
               "probe": {"topic": queued_topic, "reliability": "reliable", "durability": "transient_local"}}
    env = jazzy.environment(built, domain_id=random.randint(101, 200))
    env.update(ROS_LOG_DIR=str(tmp_path / "log"), ROS_HOME=str(tmp_path / "home"), PICK_AND_PLACE_QUIET="1")
    probed: dict[str, object] = {}

    def probe_once_active(lines: list[str]) -> bool:
        if not lines or not lines[-1].endswith("[earl_lifecycle_manager]: activated: 17 nodes"):
            return False
        result = subprocess.run([str(jazzy.python), str(GRAPH)], input=json.dumps(request), capture_output=True,
                                text=True, env=env, timeout=120)
        probed.update(json.loads(result.stdout) if result.returncode == 0 else {"error": result.stderr[-3000:]})
        return True

    lines, reached = run_until(["ros2", "launch", "pick_and_place_bringup", "system.launch.py", "period:=0.01"],
                               probe_once_active, LAUNCH_TIMEOUT, env)
    assert reached and "error" not in probed, probed.get("error", "\n".join(lines[-30:]))
    graph = probed["graph"]
    assert isinstance(graph, dict)
    for name, subscribers in expected.items():
        found = {s["node"]: s for s in graph[name]["subscriptions"]}
        for node, qos in subscribers:
            assert node in found, f"{name}: no subscription of {node} ({sorted(found)})"
            assert {k: found[node][k] for k in qos} == qos, f"{name} as {node} subscribes it: {found[node]}"
        # one publisher, the output's node, whose QoS serves every subscriber
        assert len(graph[name]["publishers"]) == 1, graph[name]
    assert probed["probe"] == {"matched": 0, "incompatible": ["RMW_QOS_POLICY_DURABILITY"]}, probed["probe"]

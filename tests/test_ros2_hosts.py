"""The ros2 target across hosts: the sample with its agents allocated to two hosts (the «Agent»
tag host: manip/a on ``arm``, grip/a and task/a on ``hand``) gets a launch file per host, each
starting only its agents and a lifecycle manager of its own, while the start barrier still
waits for the nodes of the whole system. Built with colcon, each host's launch runs in a Linux
network namespace of its own, the namespaces joined by veth pairs on a bridge in a third one:
DDS finds the other host's nodes over that network only, and manip/a.cs goes idle -> jointMove
-> idle -> emergencyStop as when one launch starts everything.

Network namespaces need root (CAP_NET_ADMIN): where ``ip netns add`` is refused the test fails
with the reason, it is never skipped."""

from __future__ import annotations

import ast
import random
import re
import secrets
import shutil
import subprocess
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.support import known_bad, ros2
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs, line_buffered, run_until, stop

ROOT = Path(__file__).resolve().parents[1]
# the ROS 2 modules share one worker of a parallel run: two launches at once could meet on a ROS domain
pytestmark = pytest.mark.xdist_group("ros2")
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"
USER = SAMPLE.parent / "user"
BRINGUP = "pick_and_place_bringup"
# the agents' part defs in the sample's SysML v2 form, and the host each gets
HOSTS = {"ManipulatorAgent": "arm", "GripperAgent": "hand", "TaskAgent": "hand"}
AGENTS_ON = {"arm": ["manip_a"], "hand": ["grip_a", "task_a"]}
NODES_ON = {"arm": 13, "hand": 4}  # manip/a: cs, 6 motor controllers, 6 motors; grip/a: 3; task/a: 1
NODES = 17
# launch prefixes each line of a process with "[<process>] "
STATE = re.compile(r"^(?:\[[^\]]+\] )?step \d+ manip/a\.cs: (?:start in (\w+)|(\w+) -> (\w+) \([^)]*\))$")
SEQUENCE = ["idle", "jointMove", "idle", "emergencyStop"]
LAUNCH_TIMEOUT = 120.0  # s: two launches, discovery over the bridge, the barrier, then about 1 s of script
# bytes each host must have received over its veth during a run: DDS discovery and the links
# between manip/a and task/a cross it (a run that went through shared memory would not)
MIN_RECEIVED = 20_000
CAMPAIGN = "ros2 hosts"  # tests/support/campaigns.toml
HOST_RUNS = loaded_runs(CAMPAIGN)

# Fast DDS, as ROS 2 Jazzy configures it, also carries data through shared memory between
# participants of one machine, and the namespaces are one machine (one /dev/shm): this profile
# leaves only UDPv4, so all traffic between the hosts goes over the veth network. The profile
# is the default one of every participant (FASTDDS_DEFAULT_PROFILES_FILE).
UDP_ONLY_PROFILE = ROOT / "tests" / "support" / "fastdds_udp_only.xml"


def with_hosts(text: str) -> str:
    """The sample's SysML v2 text with the tag host on each agent's part def."""
    for definition, host in HOSTS.items():
        head = f"part def {definition} :> Agent {{\n"
        assert text.count(head) == 1, head
        text = text.replace(head, f'{head}            @AgentHost {{ host = "{host}"; }}\n')
    return text


def launch_agents(path: Path) -> list[str]:
    """The agent namespaces of a generated launch file's AGENTS table, read without importing launch."""
    tree = ast.parse(path.read_text())
    value = next(node.value for node in tree.body if isinstance(node, ast.Assign)
                 and any(isinstance(t, ast.Name) and t.id == "AGENTS" for t in node.targets))
    return [namespace for namespace, _, _, _ in ast.literal_eval(value)]


def expected_nodes(bringup: Path) -> set[object]:
    """The expected_nodes of every node in the agents' parameter files, which every host's launch file passes."""
    return {values["expected_nodes"] for path in (bringup / "config").glob("*.yaml")
            for values in ros2.generated_parameters(path).values()}


def manip_states(lines: list[str]) -> list[str]:
    """The states manip/a.cs entered, in order, from the launch's output."""
    return [m.group(1) or m.group(3) for m in map(STATE.match, (line.strip() for line in lines)) if m]


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A colcon workspace whose src/ is gen's output for the sample with hosts (its user code
    copied into src/user/ first)."""
    ws = tmp_path_factory.mktemp("ros2_hosts_ws")
    model = ws / "pick_and_place.sysml"
    model.write_text(with_hosts(SAMPLE.read_text(encoding="utf-8")), encoding="utf-8")
    shutil.copytree(USER, ws / "src" / "user")
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "ros2", "-o",
                             str(ws / "src")], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return ws


def test_a_launch_file_per_host_starts_its_agents_and_waits_for_the_whole_system(workspace: Path) -> None:
    launch = workspace / "src" / BRINGUP / "launch"
    assert sorted(p.name for p in launch.iterdir()) == ["arm.launch.py", "hand.launch.py", "system.launch.py"]
    assert launch_agents(launch / "system.launch.py") == ["manip_a", "grip_a", "task_a"]
    for host, agents in AGENTS_ON.items():
        text = (launch / f"{host}.launch.py").read_text()
        assert launch_agents(launch / f"{host}.launch.py") == agents
        assert f'name="earl_lifecycle_manager_{host}"' in text
    assert expected_nodes(workspace / "src" / BRINGUP) == {NODES}
    assert 'name="earl_lifecycle_manager"' in (launch / "system.launch.py").read_text()


def test_the_sample_without_hosts_has_only_the_system_launch(tmp_path: Path) -> None:
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(SAMPLE), "--target", "ros2", "-o",
                             str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert sorted(p.name for p in (tmp_path / BRINGUP / "launch").iterdir()) == ["system.launch.py"]


def gen(model: Path, out: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "ros2", "-o", str(out)],
                          capture_output=True, text=True, timeout=300)


def test_untagged_agents_go_on_the_default_host_and_a_host_may_not_replace_the_system_launch(
        tmp_path: Path) -> None:
    text = SAMPLE.read_text(encoding="utf-8")
    head = "part def ManipulatorAgent :> Agent {\n"
    model = tmp_path / "pick_and_place.sysml"
    model.write_text(text.replace(head, f'{head}            @AgentHost {{ host = "arm-1"; }}\n'), encoding="utf-8")
    result = gen(model, tmp_path / "out")
    assert result.returncode == 0, result.stderr
    launch = tmp_path / "out" / BRINGUP / "launch"
    assert sorted(p.name for p in launch.iterdir()) == ["arm-1.launch.py", "default_host.launch.py",
                                                        "system.launch.py"]
    assert launch_agents(launch / "default_host.launch.py") == ["grip_a", "task_a"]
    assert 'name="earl_lifecycle_manager_arm_1"' in (launch / "arm-1.launch.py").read_text()
    # the check refuses what gen could not write: a host named system (its launch file would
    # replace system.launch.py), two hosts that are one name to ROS
    model.write_text(text.replace(head, f'{head}            @AgentHost {{ host = "system"; }}\n'), encoding="utf-8")
    result = gen(model, tmp_path / "refused")
    assert result.returncode != 0 and "D007 error: agent manip/a has host 'system'" in result.stderr, result.stderr
    assert "'system' is reserved: system.launch.py starts every agent" in result.stderr
    other = "part def GripperAgent :> Agent {\n"
    model.write_text(text.replace(head, f'{head}            @AgentHost {{ host = "arm-1"; }}\n')
                     .replace(other, f'{other}            @AgentHost {{ host = "arm_1"; }}\n'), encoding="utf-8")
    result = gen(model, tmp_path / "refused")
    assert result.returncode != 0 and "the two are one name to ROS ('arm_1')" in result.stderr, result.stderr


def test_show_and_convert_keep_the_hosts(workspace: Path, tmp_path: Path) -> None:
    converted = tmp_path / "converted.sysml"
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "convert", str(workspace / "pick_and_place.sysml"),
                             "--to", "sysml", "-o", str(converted)], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert converted.read_text(encoding="utf-8").count("@AgentHost {") == 3
    shown = subprocess.run([sys.executable, "-m", "earl_m2t", "show", str(converted)], capture_output=True, text=True,
                           timeout=300)
    assert shown.returncode == 0, shown.stderr
    hosts = {m.group(1): m.group(2) for m in re.finditer(r"^  agent (\S+) .*  host (\S+)$", shown.stdout, re.MULTILINE)}
    assert hosts == {"manip/a": "arm", "grip/a": "hand", "task/a": "hand"}


# ---------------------------------------------------------------- against a real ROS 2 Jazzy


@pytest.fixture(scope="module")
def jazzy() -> ros2.Installation:
    """The ROS 2 prefix of tests/support/ros2.py (as in tests/test_gen_ros2.py)."""
    return ros2.installation_for_tests()


@pytest.fixture(scope="module")
def built(workspace: Path, jazzy: ros2.Installation) -> Path:
    return jazzy.colcon_build(workspace)


@pytest.mark.parametrize("composed", ["true", "false"])
def test_launch_splits_the_nodes_of_the_system_launch_between_the_host_launch_files(
        built: Path, jazzy: ros2.Installation, composed: str) -> None:
    """Each launch file as launch's own loader evaluates it (tests/support/ros2_launch_description.py):
    every node of system.launch.py is started by exactly one host's launch file, the one of its
    agent, with the same remappings and parameters; each host has a lifecycle manager of its own."""
    launch = built / "install" / BRINGUP / "share" / BRINGUP / "launch"
    system = {n["name"]: n for n in jazzy.launch_description(built, launch / "system.launch.py", composed=composed)}
    assert "/earl_lifecycle_manager" in system
    on: dict[str, dict[str, dict[str, object]]] = {}
    for host in AGENTS_ON:
        nodes = jazzy.launch_description(built, launch / f"{host}.launch.py", composed=composed)
        on[host] = {n["name"]: n for n in nodes}
        assert len(on[host]) == len(nodes)
        assert f"/earl_lifecycle_manager_{host}" in on[host]
        subsystems = {name for name in on[host] if not name.startswith("/earl_lifecycle_manager")}
        assert {name.split("/")[1] for name in subsystems} == set(AGENTS_ON[host])
        assert len([name for name in subsystems if not name.endswith("_container")]) == NODES_ON[host]
    started = [name for nodes in on.values() for name in nodes if not name.startswith("/earl_lifecycle_manager")]
    assert sorted(started) == sorted(name for name in system if name != "/earl_lifecycle_manager")
    for nodes in on.values():
        for name, node in nodes.items():
            if not name.startswith("/earl_lifecycle_manager"):
                assert node == system[name]


def ip(*args: str) -> None:
    result = subprocess.run(["ip", *args], capture_output=True, text=True, timeout=30)
    if result.returncode != 0:
        raise RuntimeError(f"ip {' '.join(args)}: {result.stderr.strip() or result.returncode}")


@dataclass(frozen=True)
class Host:
    name: str  # the model's host
    netns: str
    device: str  # its end of the veth pair, inside netns
    address: str


@dataclass(frozen=True)
class Network:
    bridge_netns: str
    hosts: dict[str, Host]


@pytest.fixture
def network() -> Iterator[Network]:
    """A network namespace per host, each with lo up and a veth to a bridge in a namespace of
    its own, on a 10.213.N.0/24 of this run (multicast routed to the veth, for DDS discovery).
    Names unique per run; everything is deleted at the end, whatever happened."""
    if shutil.which("ip") is None:
        pytest.fail("no ip command (iproute2): the hosts run in network namespaces", pytrace=False)
    token = secrets.token_hex(3)
    subnet = random.randint(1, 254)
    bridge_netns = f"earl-{token}-bridge"
    hosts = {name: Host(name, f"earl-{token}-{name}", f"e{token}{k}", f"10.213.{subnet}.{k + 1}/24")
             for k, name in enumerate(sorted(AGENTS_ON))}
    made: list[str] = []
    try:
        try:
            ip("netns", "add", bridge_netns)
        except RuntimeError as refused:
            pytest.fail(f"cannot create a network namespace (the test needs root): {refused}", pytrace=False)
        made.append(bridge_netns)
        ip("-n", bridge_netns, "link", "add", "br0", "type", "bridge", "mcast_snooping", "0")
        ip("-n", bridge_netns, "link", "set", "br0", "up")
        for host in hosts.values():
            ip("netns", "add", host.netns)
            made.append(host.netns)
            peer = host.device + "b"
            ip("link", "add", host.device, "netns", host.netns, "type", "veth", "peer", "name", peer,
               "netns", bridge_netns)
            ip("-n", bridge_netns, "link", "set", peer, "master", "br0")
            ip("-n", bridge_netns, "link", "set", peer, "up")
            ip("-n", host.netns, "link", "set", "lo", "up")
            ip("-n", host.netns, "addr", "add", host.address, "dev", host.device)
            ip("-n", host.netns, "link", "set", host.device, "up", "multicast", "on")
            ip("-n", host.netns, "route", "add", "224.0.0.0/4", "dev", host.device)
        yield Network(bridge_netns, hosts)
    finally:
        for netns in reversed(made):  # deleting a namespace deletes its veth ends and bridge
            subprocess.run(["ip", "netns", "delete", netns], capture_output=True, timeout=30)


def received_bytes(host: Host) -> int:
    counter = f"/sys/class/net/{host.device}/statistics/rx_bytes"
    result = subprocess.run(["ip", "netns", "exec", host.netns, "cat", counter], capture_output=True, text=True,
                            timeout=30)
    assert result.returncode == 0, result.stderr
    return int(result.stdout)


def hosts_environment(built: Path, jazzy: ros2.Installation) -> dict[str, str]:
    """The launches' environment: DDS over UDP alone, discovery across the subnet."""
    profile = UDP_ONLY_PROFILE
    env = jazzy.environment(built)
    # the prefix's env.sh keeps discovery on the machine's loopback; here it crosses the veths
    env.update(ROS_AUTOMATIC_DISCOVERY_RANGE="SUBNET", FASTDDS_DEFAULT_PROFILES_FILE=str(profile),
               FASTRTPS_DEFAULT_PROFILES_FILE=str(profile), PICK_AND_PLACE_QUIET="1")
    env.pop("ROS_LOCALHOST_ONLY", None)
    env.pop("ROS_STATIC_PEERS", None)
    return env


@pytest.mark.loaded
def test_hosts_in_network_namespaces_take_manip_cs_through_the_states_of_the_model(
        built: Path, jazzy: ros2.Installation, network: Network, tmp_path: Path) -> None:
    """hand's launch in one namespace, arm's in another, on one ROS domain, composed at 1 ms
    periods, under a CPU hog per core; each run stops as soon as manip/a.cs (on arm) reached
    emergencyStop. HOST_RUNS runs, each on a ROS domain of its own."""
    env = hosts_environment(built, jazzy)
    arm, hand = network.hosts["arm"], network.hosts["hand"]
    failures: list[str] = []
    with cpu_hogs():  # under a CPU hog per core, as the system's launches
        for attempt in range(1, HOST_RUNS + 1):
            env["ROS_DOMAIN_ID"] = str(random.randint(1, 100))
            failure = run_across_hosts(arm, hand, env, tmp_path / f"run{attempt}")
            if failure:
                failures.append(f"run {attempt}: {failure}")
    print(f"\nros2 launches across 2 hosts, composed, period 1 ms, under load: {HOST_RUNS - len(failures)} of "
          f"{HOST_RUNS} completed the sequence")
    assert not failures, f"{len(failures)} of {HOST_RUNS} launches failed:\n" + "\n".join(failures[:2])


def run_across_hosts(arm: Host, hand: Host, env: dict[str, str], folder: Path,
                     seen: Callable[[list[str]], bool] | None = None) -> str:
    """One launch on each host, until manip/a.cs reached emergencyStop on arm (or ``seen``
    held); what went wrong, or an empty string."""
    def host_env(host: Host) -> dict[str, str]:
        return {**env, "ROS_LOG_DIR": str(folder / host.name / "log"), "ROS_HOME": str(folder / host.name)}

    def launch(host: Host) -> list[str]:
        return ["ip", "netns", "exec", host.netns, *line_buffered(
            ["ros2", "launch", BRINGUP, f"{host.name}.launch.py", "period:=0.001", "composed:=true"])]

    received = {host.name: received_bytes(host) for host in (arm, hand)}
    folder.mkdir(parents=True)
    hand_log = folder / "hand.out"
    with hand_log.open("w") as out:
        hand_run = subprocess.Popen(launch(hand), stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                    env=host_env(hand), text=True, start_new_session=True)
        try:
            lines, reached = run_until(launch(arm), seen or (lambda out: "emergencyStop" in manip_states(out)),
                                       LAUNCH_TIMEOUT, host_env(arm))
        finally:
            stop(hand_run)
    hand_lines = hand_log.read_text(errors="replace").splitlines()
    notable = [f"arm: {line}" for line in lines if re.search(r"a\.cs: |WARN|ERROR|died|manager", line)]
    notable += [f"hand: {line}" for line in hand_lines if re.search(r"WARN|ERROR|died|manager", line)]
    context = "\n".join(notable[:80] + ["...", "arm:"] + lines[-20:] + ["hand:"] + hand_lines[-20:])
    if not reached or manip_states(lines)[:4] != SEQUENCE:
        return f"{manip_states(lines)}\n{context}"
    # each host's own manager configured, then activated, only that host's nodes
    for host, host_lines in (("arm", lines), ("hand", hand_lines)):
        if not any(line.endswith(f"[earl_lifecycle_manager_{host}]: activated: {NODES_ON[host]} nodes")
                   for line in host_lines):
            return f"{host}'s manager did not activate its {NODES_ON[host]} nodes\n{context}"
    # the hosts talked over the veth network
    for host in (arm, hand):
        got = received_bytes(host) - received[host.name]
        if got < MIN_RECEIVED:
            return f"{host.name} received {got} bytes on its veth"
    return ""


def latest_value_built(jazzy: ros2.Installation, folder: Path) -> Path:
    """The known-bad variant's workspace with the hosts (tests/support/known_bad.py), built (once
    per content: tests/test_campaign_builds.py builds it among the parallel tests)."""
    ws = folder / "ws"
    model = known_bad.one_shot_into_latest_value(folder / "model", with_hosts(SAMPLE.read_text(encoding="utf-8")))
    shutil.copytree(USER, ws / "src" / "user")
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "ros2", "-o",
                             str(ws / "src")], capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return jazzy.colcon_build(ws)


@pytest.mark.loaded
def test_the_checks_across_hosts_catch_a_one_shot_command_into_a_latest_value_input(
        jazzy: ros2.Installation, network: Network, tmp_path: Path) -> None:
    """The known-bad variant (tests/support/known_bad.py) with the same hosts: manip/a.cs's
    commands a latest-value link across the two hosts and manip/a.cs on its own clock. Under
    load, a later command overwrites the setpoint before manip/a.cs reads it in one of the
    runs the campaign keeps."""
    built = latest_value_built(jazzy, tmp_path)
    env = hosts_environment(built, jazzy)
    arm, hand = network.hosts["arm"], network.hosts["hand"]
    caught = None
    with cpu_hogs():
        for attempt in range(1, catch_runs(CAMPAIGN) + 1):
            env["ROS_DOMAIN_ID"] = str(random.randint(1, 100))
            if run_across_hosts(arm, hand, env, tmp_path / f"run{attempt}", known_bad.SetpointWatch(manip_states)):
                caught = attempt
                break
    print(f"\nros2 latest-value variant across hosts: caught in run {caught}")
    assert caught is not None, f"all {catch_runs(CAMPAIGN)} runs of the latest-value variant reached the sequence"

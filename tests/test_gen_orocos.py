"""The Orocos RTT target (FABRIC's own reading of its FABRIC files is tests/test_fabric_files.py):
the deployer scripts name only components, ports and component types
that the generated C++ defines, the run-time configurations agree with the scripts, output is
deterministic and user files are never overwritten; against a real Orocos RTT 2.9 and OCL
(tests/support/orocos.py finds or builds them) the generated project compiles warning-free with
-Werror, and OCL's deployer runs deploy/system.ops through the model's states."""

from __future__ import annotations

import os
import re
import select
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import GenError, generate, render
from tests.support import known_bad, orocos
from tests.support.campaign import catch_runs, loaded_runs
from tests.support.load import cpu_hogs, run_until

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
USER = SAMPLE.parent / "user"
# the operations of OCL's DeploymentComponent that the generated scripts may call
DEPLOYER_OPERATIONS = {"import", "loadComponent", "setActivity", "setMasterSlaveActivity", "connect",
                       "configureComponent", "startComponent", "runScript"}
CALL = re.compile(r"^(\w+)\((.*)\)$")
POLICY_FIELD = re.compile(r"^\w+\.(?:type|size) = \d+$")  # a ConnPolicy's buffer type and size
ARGUMENT = re.compile(r'"([^"]*)"|([\w.]+)')


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)


@pytest.fixture(scope="module")
def out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """gen's output for the sample, with the sample's user code copied in first."""
    folder = tmp_path_factory.mktemp("orocos")
    shutil.copytree(USER, folder / "user")
    result = earl("gen", str(SAMPLE), "--target", "orocos", "-o", str(folder))
    assert result.returncode == 0, result.stderr
    return folder


# ---------------------------------------------------------------- what the generated C++ defines


class Component:
    def __init__(self) -> None:
        self.inputs: set[str] = set()
        self.outputs: set[str] = set()
        self.services: dict[str, set[str]] = {}


def components_of(source: str) -> dict[str, Component]:
    """Component type (as ORO_LIST_COMPONENT_TYPE registers it) -> its ports and operations,
    read from the text of a generated components.cpp."""
    namespace = re.search(r"^namespace ([\w:]+) \{$", source, re.M)
    assert namespace is not None
    listed = re.findall(r"^ORO_LIST_COMPONENT_TYPE\(([\w:]+)\)$", source, re.M)
    assert re.search(r"^ORO_CREATE_COMPONENT_LIBRARY\(\)$", source, re.M)
    found: dict[str, Component] = {}
    for block in re.split(r"^class (?=\w+ final : public RTT::TaskContext)", source, flags=re.M)[1:]:
        name = block.split()[0]
        component = Component()
        members = {m: kind for kind, m in re.findall(r"^  RTT::(Input|Output)Port<.*> (\w+);$", block, re.M)}
        for port, member in re.findall(r'add(?:Event)?Port\("(\w+)", (\w+)\)', block):
            (component.inputs if members[member] == "Input" else component.outputs).add(port)
        for service, operation in re.findall(r'(\w+)->addOperation\("(\w+)"', block):
            component.services.setdefault(service, set()).add(operation)
        found[f"{namespace.group(1)}::{name}"] = component
    assert sorted(found) == sorted(listed), "every TaskContext is listed once, and only those"
    return found


@pytest.fixture(scope="module")
def types(out: Path) -> dict[str, Component]:
    found: dict[str, Component] = {}
    for source in sorted(out.glob("orocos/*/*/components.cpp")):
        found.update(components_of(source.read_text(encoding="utf-8")))
    return found


def calls(script: Path) -> list[tuple[str, list[str]]]:
    result = []
    for line in script.read_text(encoding="utf-8").splitlines():
        if not line or line.startswith("//") or line.startswith("var ConnPolicy ") or POLICY_FIELD.match(line):
            continue
        match = CALL.match(line)
        assert match, f"{script.name}: {line}"
        arguments = [m.group(1) if m.group(1) is not None else m.group(2) for m in ARGUMENT.finditer(match.group(2))]
        result.append((match.group(1), arguments))
    return result


def deployed(out: Path) -> tuple[dict[str, str], list[tuple[str, str]], list[str]]:
    """(component -> type, connections, operations in order) of deploy/system.ops and the
    scripts it runs, as the deployer would execute them."""
    loaded: dict[str, str] = {}
    connections: list[tuple[str, str]] = []
    order: list[str] = []

    def execute(name: str) -> None:
        for operation, arguments in calls(out / "deploy" / name):
            order.append(operation)
            assert operation in DEPLOYER_OPERATIONS, operation
            if operation == "runScript":
                execute(arguments[0])
            elif operation == "loadComponent":
                assert arguments[0] not in loaded
                loaded[arguments[0]] = arguments[1]
            elif operation == "connect":
                connections.append((arguments[0], arguments[1]))
            elif operation == "setActivity":
                assert arguments[0] in loaded and arguments[3] == "ORO_SCHED_OTHER"
            elif operation == "setMasterSlaveActivity":
                assert arguments[0] in loaded and arguments[1] in loaded
            elif operation in ("configureComponent", "startComponent"):
                assert arguments[0] in loaded, arguments

    execute("system.ops")
    return loaded, connections, order


# ---------------------------------------------------------------- tests


def test_gen_writes_a_library_per_definition_and_scripts_and_fabric_files_per_instance(out: Path) -> None:
    model = load(SAMPLE).model
    assert len(list(out.glob("orocos/*/*/components.cpp"))) == len(list(model.definitions())) == 7
    assert len(list(out.glob("fabric/*/spec/subsystem.xml"))) == 7
    assert len(list(out.glob("fabric/*/config/*.xml"))) == len(model.subsystems) == 17
    assert len(list(out.glob("deploy/*.ops"))) == 17 + 1
    assert (out / "CMakeLists.txt").is_file() and (out / "runtime" / "earl" / "subsystem.hpp").is_file()
    assert (out / "generated" / "include" / "PickAndPlace" / "manip_a" / "cs" / "subsystem.hpp").is_file()


def test_the_scripts_name_only_component_types_components_and_ports_of_the_generated_code(
        out: Path, types: dict[str, Component]) -> None:
    loaded, connections, order = deployed(out)
    assert set(loaded.values()) == set(types), "every generated component type is deployed"
    for source, target in connections:
        source_component, _, source_port = source.partition(".")
        target_component, _, target_port = target.partition(".")
        assert source_port in types[loaded[source_component]].outputs, source
        assert target_port in types[loaded[target_component]].inputs, target
    assert len(set(connections)) == len(connections)
    # every input port of every component is connected (each buffer of the sample is linked)
    for name, type_name in loaded.items():
        for port in types[type_name].inputs:
            assert any(t == f"{name}.{port}" for _, t in connections), f"{name}.{port} is not connected"
    # start after every connection, the pf components before their masters
    assert order.index("startComponent") > max(i for i, op in enumerate(order) if op == "connect")


def test_the_links_of_the_model_are_exactly_the_connections_of_system_ops(out: Path) -> None:
    links = [c for c in calls(out / "deploy" / "system.ops") if c[0] == "connect"]
    model = load(SAMPLE).model
    assert len(links) == len(model.links) == 32
    ends = {(a[0], a[1]) for _, a in links}
    assert ("task_a_cs.manipulatorCommand_ob", "manip_a_cs.manipulatorCommand_ib") in ends
    assert ("manip_a_motorController3_ve.motorControllerState_ob", "manip_a_cs.motorControllerStateK_ib_3") in ends


def test_the_run_time_configurations_are_what_the_scripts_deploy(out: Path) -> None:
    """Each instance's FABRIC configuration holds the pf components its deployer script loads
    beside its master (FABRIC's deployer creates the master itself)."""
    loaded, _, _ = deployed(out)
    for path in sorted(out.glob("fabric/*/config/*.xml")):
        instance = path.stem
        root = ElementTree.parse(path).getroot()
        assert {i.get("package") for i in root.iter("import")} == {"pick_and_place_orocos"}
        configured = sorted(c.get("type", "") for c in root.iter("component"))
        scripted = sorted(t for name, t in loaded.items() if name.startswith(f"{instance}_"))
        assert configured == scripted, path
        assert loaded[instance].endswith("::orocos::Master")


def test_the_subsystem_models_name_the_components_and_ports_that_exist(out: Path, types: dict[str, Component]) -> None:
    for path in sorted(out.glob("fabric/*/config/*.xml")):
        root = ElementTree.parse(path).getroot()
        components = {c.get("name", ""): c.get("type", "") for c in root.iter("component")}
        for connection in root.iter("connection"):
            for end, ports in ((connection.get("from", ""), "outputs"), (connection.get("to", ""), "inputs")):
                component, _, port = end.partition(".")
                if component in components:
                    assert port in getattr(types[components[component]], ports), (path, end)
        spec = ElementTree.parse(path.parent.parent / "spec" / "subsystem.xml").getroot()
        assert {r.get("name") for r in spec.iter("running_component")} <= set(components)


def test_regenerating_gives_identical_bytes_and_rewrites_nothing(tmp_path: Path) -> None:
    model = load(SAMPLE).model
    first = generate(model, tmp_path / "a", "orocos")
    assert first.write.written and first.write.created
    second = generate(model, tmp_path / "a", "orocos")
    assert second.write.written == () and second.write.created == ()
    assert render(load(SAMPLE).model, "orocos") == render(model, "orocos")


def test_a_user_file_edit_survives_regeneration(tmp_path: Path) -> None:
    model = load(SAMPLE).model
    generate(model, tmp_path, "orocos")
    user = tmp_path / "user" / "manip_a" / "cs" / "jointMove_pf.hpp"
    edited = user.read_text(encoding="utf-8") + "// mine\n"
    user.write_text(edited, encoding="utf-8")
    report = generate(model, tmp_path, "orocos")
    assert "user/manip_a/cs/jointMove_pf.hpp" in report.write.kept
    assert user.read_text(encoding="utf-8") == edited


def test_colliding_component_names_are_refused_in_one_line(tmp_path: Path) -> None:
    # the instance grip_a_cs_gripperControl_pf would be named as the pf component of grip/a.cs
    text = SAMPLE.read_text(encoding="utf-8").replace('name="fingerMotor/re" type=',
                                                      'name="cs_gripperControl_pf" type=')
    model = tmp_path / "model.uml"
    model.write_text(text, encoding="utf-8")
    shutil.copy(SAMPLE.parent / "EARL.profile.uml", tmp_path / "EARL.profile.uml")
    with pytest.raises(GenError, match=r"^D004 grip/a\.cs_gripperControl_pf: the component name "
                                       r"grip_a_cs_gripperControl_pf is also that of grip/a\.cs pf gripperControl_pf$"):
        render(load(model).model, "orocos")
    result = earl("gen", str(model), "--target", "orocos", "-o", str(tmp_path / "out"))
    assert result.returncode != 0 and len(result.stderr.splitlines()) == 1 and "Traceback" not in result.stderr


# The thermostat with a second output of its control subsystem, boostCommand/ob, linked to the
# heater driver's command/ib beside heaterCommand/ob: one Input Buffer fed by two links, which
# EARL allows (check passes it; the ROS target gives a topic per link).
TWO_LINKS = {
    "            interface 'cs,heaterDriver/ve' : InterSubsystemLink connect cs.'heaterCommand/ob' to "
    "'heaterDriver/ve'.'command/ib';\n":
    "            interface 'cs,heaterDriver/ve' : InterSubsystemLink connect cs.'heaterCommand/ob' to "
    "'heaterDriver/ve'.'command/ib';\n"
    "            interface 'cs,heaterDriver/ve/2' : InterSubsystemLink connect cs.'boostCommand/ob' to "
    "'heaterDriver/ve'.'command/ib';\n",
    "            port 'heaterCommand/ob' : OutputBuffer { attribute :>> msg : DataTypes::HeaterCommand; }\n":
    "            port 'heaterCommand/ob' : OutputBuffer { attribute :>> msg : DataTypes::HeaterCommand; }\n"
    "            port 'boostCommand/ob' : OutputBuffer { attribute :>> msg : DataTypes::HeaterCommand; }\n",
    "                out 'heaterCommand/ob';\n":
    "                out 'heaterCommand/ob';\n                out 'boostCommand/ob';\n",
}


def test_an_input_buffer_fed_by_several_links_is_connected_to_each_and_fabric_is_told_in_a_note(
        tmp_path: Path) -> None:
    text = (ROOT / "tests" / "fixtures" / "sysml2" / "thermostat.sysml").read_text(encoding="utf-8")
    for old, new in TWO_LINKS.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    model = tmp_path / "two_links.sysml"
    model.write_text(text, encoding="utf-8")
    assert earl("check", str(model)).returncode == 0
    out = tmp_path / "out"
    result = earl("gen", str(model), "--target", "orocos", "-o", str(out))
    assert result.returncode == 0, result.stderr
    connections = [tuple(a[:2]) for op, a in calls(out / "deploy" / "system.ops") if op == "connect"]
    assert ("thermostat_a_cs.heaterCommand_ob", "thermostat_a_heaterDriver_ve.command_ib") in connections
    assert ("thermostat_a_cs.boostCommand_ob", "thermostat_a_heaterDriver_ve.command_ib") in connections
    assert (out / "deploy" / "thermostat_a_heaterDriver_ve.ops").is_file()
    assert (out / "orocos" / "thermostat_a" / "heaterDriver_ve" / "components.cpp").is_file()
    # FABRIC's deployer names one IPC channel per buffer: that instance's configuration is left
    # out, said in one note; the instances whose buffers read one channel keep theirs
    assert not (out / "fabric" / "thermostat_a_heaterDriver_ve" / "config").exists()
    assert (out / "fabric" / "thermostat_a_heaterDriver_ve" / "spec" / "subsystem.xml").is_file()
    assert (out / "fabric" / "thermostat_a_heater_re" / "config" / "thermostat_a_heater_re.xml").is_file()
    notes = [line for line in result.stdout.splitlines() + result.stderr.splitlines()
             if "FABRIC reads an Input Buffer from one IPC channel" in line]
    assert notes == ["note: thermostat/a.heaterDriver/ve: FABRIC reads an Input Buffer from one IPC channel, and "
                     "thermostat/a.heaterDriver/ve.command/ib is fed by 2 channels (thermostat_a_cs_heaterCommand, "
                     "thermostat_a_cs_boostCommand): fabric/thermostat_a_heaterDriver_ve/config/"
                     "thermostat_a_heaterDriver_ve.xml is not written (the Orocos components and deploy/ connect "
                     "every link)"], result.stdout + result.stderr


# ---------------------------------------------------------------- against a real RTT and OCL


@pytest.fixture(scope="module")
def rtt() -> orocos.Installation:
    """The RTT/OCL installation of tests/support/orocos.py. With ../shared/vendor/orocos beside
    the checkout a missing or failed build is a failure (never a skip), with the build log's tail."""
    try:
        return orocos.installation()
    except orocos.OrocosBuildFailed as failure:
        pytest.fail(str(failure), pytrace=False)
    except orocos.OrocosUnavailable as reason:
        if orocos.VENDOR.is_dir() or os.environ.get("OROCOS_RTT_PREFIX"):
            pytest.fail(str(reason), pytrace=False)
        pytest.skip(str(reason))


@pytest.fixture(scope="module")
def project(out: Path, rtt: orocos.Installation) -> Path:
    """The sample's Orocos project built against RTT and installed (tests/support/orocos.py):
    the folder of build/, install/ and build.log, the compiler's output for the warning check."""
    return orocos.built_project(out, rtt)


@pytest.fixture(scope="module")
def installed(project: Path) -> Path:
    return project / "install"


def test_the_generated_project_compiles_and_links_against_rtt(out: Path, project: Path, installed: Path) -> None:
    assert "warning:" not in (project / "build.log").read_text()
    # every component library was compiled with -Wall -Wextra -Werror (the flags CMake used)
    flags = sorted((project / "build").glob("CMakeFiles/*.dir/flags.make"))
    assert len(flags) == 7 and all("-Wall -Wextra -Werror" in f.read_text() for f in flags)
    libraries = sorted(p.name for p in (project / "build").rglob("lib*-gnulinux.so"))
    assert libraries == sorted(f"lib{p.parent.parent.name}_{p.parent.name}-gnulinux.so"
                               for p in out.glob("orocos/*/*/components.cpp"))
    assert len(libraries) == 7
    installed_libraries = sorted(p.name for p in installed.rglob("lib*-gnulinux.so"))
    assert installed_libraries == libraries


DEPLOYER_STATE = re.compile(r"^step (\d+) manip_a_cs: (?:start in (\w+)|(\w+) -> (\w+) \([^)]*\))$")
LOADED = re.compile(r"Adding (\w+) as new peer:\s+OK\.")
ERROR = re.compile(r"\[\s*ERROR\s*\]")
CONNECTED = re.compile(r"Connected Port ([\w.]+) to\s+([\w.]+)\.")


def script_calls(deploy: Path, operation: str) -> list[list[str]]:
    """The arguments of every call of one deployer operation in every generated script."""
    calls = []
    for script in sorted(deploy.glob("*.ops")):
        for line in script.read_text().splitlines():
            match = CALL.match(line.strip())
            if match and match.group(1) == operation:
                calls.append([quoted or bare for quoted, bare in ARGUMENT.findall(match.group(2))])
    return calls


def run_deployer(deploy: Path, env: dict[str, str], until: str, seconds: float) -> tuple[list[str], int, int]:
    """Runs `deployer -s system.ops` headless (no terminal on stdin) from deploy/ until manip/a.cs
    reaches the state `until` or the time is up, then stops it with SIGINT as a user would.
    Returns (its output lines, its exit status, the process group that must be gone); its stderr,
    where RTT's logger writes a line in pieces that another thread's line could land between,
    goes to deploy/deployer.stderr."""
    with open(deploy / "deployer.stderr", "wb") as stderr:
        process = subprocess.Popen(["deployer", "-l", "info", "-s", "system.ops"], cwd=deploy, env=env,
                                   stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=stderr,
                                   start_new_session=True)
    assert process.stdout is not None
    lines: list[str] = []
    buffered = ""
    deadline = time.monotonic() + seconds
    fd = process.stdout.fileno()
    try:
        while time.monotonic() < deadline and process.poll() is None:
            ready, _, _ = select.select([fd], [], [], 0.05)
            buffered += os.read(fd, 65536).decode(errors="replace") if ready else ""
            *complete, buffered = buffered.split("\n")
            lines.extend(complete)
            if any(f"-> {until} " in line for line in complete if "manip_a_cs:" in line):
                time.sleep(0.1)  # a few more periods: the other masters' reactions, no error after
                break
        process.send_signal(signal.SIGINT)
        rest, _ = process.communicate(timeout=30)
        lines.extend((buffered + rest.decode(errors="replace")).splitlines())
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
    return lines, process.returncode, process.pid


def group_is_gone(group: int) -> bool:
    try:
        os.killpg(group, 0)
    except ProcessLookupError:
        return True
    return False


def at_period(deploy: Path, folder: Path, period: float) -> Path:
    """A copy of deploy/ whose periodic masters run every `period` seconds (the scripts'
    setActivity, as a user sets it); the masters activated by buffer groups keep their own
    activity, which data and their deadlines wake."""
    shutil.copytree(deploy, folder)
    for script in folder.glob("*.ops"):
        text = script.read_text()
        script.write_text(re.sub(r'^(setActivity\("\w+", )0\.01(, )', rf"\g<1>{period}\g<2>", text, flags=re.M))
    return folder


def deployer_states(lines: list[str]) -> list[str]:
    return [m.group(2) or m.group(4) for m in map(DEPLOYER_STATE.match, (line.strip() for line in lines)) if m]


CAMPAIGN = "orocos pick_and_place"  # tests/support/campaigns.toml
LOADED_RUNS = loaded_runs(CAMPAIGN)
SEQUENCE = ["idle", "jointMove", "idle", "emergencyStop"]
# The periodic masters at 2 ms: 17 masters (and 24 pf components) at 1 ms do not keep up on
# two cores with a busy process per core, so each run would take the timeout; at 2 ms a run
# takes about 4 s (1 s start-up, 1.7 s of the sample's script, then stopped at once).
LOADED_PERIOD = 0.002


@pytest.mark.loaded
def test_ocls_deployer_runs_the_system_through_the_states_of_the_model(out: Path, installed: Path,
                                                                      rtt: orocos.Installation,
                                                                      tmp_path: Path) -> None:
    """50 deployments with one busy process per CPU, each stopped as soon as manip/a.cs reached
    emergencyStop: task/a.cs's one-shot setpoint reaches manip/a.cs through a buffer connection
    (a queue of 8) and activates it, so it is never lost. The first run is stopped with SIGINT
    as a user would, and its output and OCL's log are checked in full; the others are killed
    at once once in emergencyStop, and their output, stderr and OCL's log hold no error."""
    deploy = at_period(out / "deploy", tmp_path / "deploy", LOADED_PERIOD)
    assert "queue8.size = 8" in (deploy / "system.ops").read_text()
    env = rtt.environment([installed / "lib" / "orocos"])
    failures = []
    with cpu_hogs():
        lines, status, group = run_deployer(deploy, env, until="emergencyStop", seconds=60)
        trace = "\n".join(line for line in lines if "manip/a.cs: q" not in line)[-4000:]
        if deployer_states(lines)[:4] != SEQUENCE:
            failures.append(f"run 1: {deployer_states(lines)}\n{trace[-1500:]}")
        # OCL's own log: every component of the scripts loaded, every connection made, no error
        log = (deploy / "orocos.log").read_text(errors="replace").splitlines()
        stderr = (deploy / "deployer.stderr").read_text(errors="replace").splitlines()
        assert not [line for line in lines + stderr + log if ERROR.search(line)], trace
        loaded = {m.group(1) for m in map(LOADED.search, log) if m}
        assert loaded == {arguments[0] for arguments in script_calls(deploy, "loadComponent")}
        assert len(loaded) == 41
        connected = [(m.group(1), m.group(2)) for m in map(CONNECTED.search, log) if m]
        connects = [(arguments[0], arguments[1]) for arguments in script_calls(deploy, "connect")]
        assert sorted(connected) == sorted(connects) and len(connects) == 187
        # SIGINT stops it cleanly, and nothing of it is left running
        assert "DeploymentComponent: Got interrupt !" in lines and status == 0, trace
        assert group_is_gone(group)
        for attempt in range(1, LOADED_RUNS):
            lines, reached = run_until(["deployer", "-l", "info", "-s", "system.ops"],
                                       lambda out: "emergencyStop" in deployer_states(out), 60, env, cwd=deploy,
                                       graceful=False, stderr=deploy / "deployer.stderr")
            if not reached or deployer_states(lines)[:4] != SEQUENCE:
                failures.append(f"run {attempt + 1}: {deployer_states(lines)}\n" + "\n".join(lines[-30:]))
            written = [(deploy / name).read_text(errors="replace").splitlines()
                       for name in ("deployer.stderr", "orocos.log")]
            errors = [line for line in lines + written[0] + written[1] if ERROR.search(line)]
            if errors:
                failures.append(f"run {attempt + 1}: {len(errors)} error line(s), first: {errors[0]}")
    assert not failures, (f"{len(failures)} of {LOADED_RUNS} deployments missed the sequence:\n"
                          + "\n".join(failures[:3]))


def latest_value_installed(rtt: orocos.Installation, folder: Path) -> tuple[Path, Path]:
    """(gen's output, the install prefix) of the known-bad variant (tests/support/known_bad.py),
    built once per content: tests/test_campaign_builds.py builds it among the parallel tests."""
    out = folder / "out"
    shutil.copytree(USER, out / "user")
    result = earl("gen", str(known_bad.one_shot_into_latest_value(folder / "model")), "--target", "orocos",
                  "-o", str(out))
    assert result.returncode == 0, result.stderr
    return out, orocos.built_project(out, rtt) / "install"


@pytest.mark.loaded
def test_the_deployer_checks_catch_a_one_shot_command_into_a_latest_value_input(rtt: orocos.Installation,
                                                                               tmp_path: Path) -> None:
    """The known-bad variant (tests/support/known_bad.py): manip/a.cs's commands a data
    connection (the latest value) and manip/a.cs's master periodic on a clock of its own,
    slower than task/a.cs's (10 ms against 2 ms: what rule C009 warns of). Deployed under load,
    a later command overwrites the setpoint before manip/a.cs reads it in one of the
    deployments the campaign keeps. (With both at 2 ms it happens in about one deployment in
    twelve: too rare for the campaign's runs to show.)"""
    out, installed = latest_value_installed(rtt, tmp_path)
    deploy = at_period(out / "deploy", tmp_path / "deploy", LOADED_PERIOD)
    manip = deploy / "manip_a_cs.ops"
    slower = f'setActivity("manip_a_cs", {LOADED_PERIOD}, ', f'setActivity("manip_a_cs", {5 * LOADED_PERIOD}, '
    assert manip.read_text().count(slower[0]) == 1
    manip.write_text(manip.read_text().replace(*slower))
    env = rtt.environment([installed / "lib" / "orocos"])

    def missed() -> bool:
        lines, _ = run_until(["deployer", "-l", "info", "-s", "system.ops"],
                             known_bad.SetpointWatch(deployer_states), 60, env, cwd=deploy, graceful=False,
                             stderr=deploy / "deployer.stderr")
        return deployer_states(lines)[:4] != SEQUENCE

    with cpu_hogs():
        caught = next((attempt for attempt in range(1, catch_runs(CAMPAIGN) + 1) if missed()), None)
    print(f"\norocos latest-value variant: caught in deployment {caught}")
    assert caught is not None, (f"all {catch_runs(CAMPAIGN)} deployments of the latest-value variant reached "
                                "the sequence")

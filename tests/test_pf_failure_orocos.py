"""A failing pf puts its subsystem in error on Orocos: the pick_and_place sample built against
RTT with the user code of tests/support/faulty_user.py and run by OCL's deployer. When
jointMove/pf throws in its pf component, or outputMotorCon/pf writes NaN, the master of
manip/a.cs sees it and takes manip/a.cs idle -> jointMove -> emergencyStop; RTT's Logger names
the pf and the reason; the deployer keeps running and the master keeps stepping. With the
masters' property non_finite = "report" the NaN is reported, sent, and changes no state."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from tests.support import orocos
from tests.support.faulty_user import NAN_FROM, THROWN, copy_faulty_user
from tests.support.load import run_until
from tests.test_gen_orocos import deployer_states, earl

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
TRACE = re.compile(r"^step (\d+) manip/a\.cs: i ")
AFTER = 20  # iterations of manip/a.cs seen after the event: it keeps stepping (at some 30 a second)
TIMEOUT = 120.0


@pytest.fixture(scope="module")
def deployment(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, str]]:
    """(deploy/, the deployer's environment) of the sample with the faulty user code, built
    against RTT and installed."""
    try:
        rtt = orocos.installation()
    except (orocos.OrocosBuildFailed, orocos.OrocosUnavailable) as reason:
        pytest.fail(str(reason), pytrace=False)
    out = tmp_path_factory.mktemp("pf_failure_orocos")
    copy_faulty_user(out / "user")
    result = earl("gen", str(SAMPLE), "--target", "orocos", "-o", str(out))
    assert result.returncode == 0, result.stderr
    installed = orocos.built_project(out, rtt) / "install"
    return out / "deploy", rtt.environment([installed / "lib" / "orocos"])


def manip_step(lines: list[str]) -> int:
    steps = [int(m.group(1)) for m in map(TRACE.match, (line.strip() for line in lines)) if m]
    return steps[-1] if steps else -1


def deploy(deployment: tuple[Path, dict[str, str]], fault: str, until: str) -> tuple[list[str], list[str]]:
    """(the deployer's output, OCL's log) of one run with EARL_FAULT=fault, stopped with SIGINT
    once ``until`` was printed and manip/a.cs stepped AFTER more times."""
    folder, env = deployment
    seen_at: list[int] = []

    def done(lines: list[str]) -> bool:
        if not seen_at and any(until in line for line in lines):
            seen_at.append(manip_step(lines))
        return bool(seen_at) and manip_step(lines) >= seen_at[0] + AFTER

    log = folder / "orocos.log"
    log.unlink(missing_ok=True)
    lines, reached = run_until(["deployer", "-l", "info", "-s", "system.ops"], done, TIMEOUT,
                               {**env, "EARL_FAULT": fault}, cwd=folder, stderr=folder / "deployer.stderr")
    assert reached, f"{until!r} and {AFTER} more iterations not seen:\n" + "\n".join(lines[-60:])
    return lines, log.read_text(errors="replace").splitlines()


def with_policy(deployment: tuple[Path, dict[str, str]], policy: str, folder: Path) -> tuple[Path, dict[str, str]]:
    """A copy of deploy/ whose instance scripts set their master's non_finite property."""
    source, env = deployment
    subprocess.run(["cp", "-r", str(source), str(folder)], check=True)
    for script in folder.glob("*.ops"):
        master, text = script.stem, script.read_text()
        configure = f'configureComponent("{master}")'
        if configure in text:
            script.write_text(text.replace(configure, f'{master}.non_finite = "{policy}"\n{configure}'))
    return folder, env


def test_a_pf_component_that_throws_takes_manip_to_its_emergency_stop(
        deployment: tuple[Path, dict[str, str]]) -> None:
    lines, log = deploy(deployment, "throw", "jointMove -> emergencyStop")
    assert deployer_states(lines) == ["idle", "jointMove", "emergencyStop"]
    failed = [line for line in log if "failed:" in line]
    assert len(failed) == 1 and "ERROR" in failed[0], failed
    assert failed[0].endswith(f"manip_a_cs: jointMove/pf failed: {THROWN}")


def test_a_nan_written_fails_the_pf(deployment: tuple[Path, dict[str, str]]) -> None:
    lines, log = deploy(deployment, "nan", "jointMove -> emergencyStop")
    assert deployer_states(lines) == ["idle", "jointMove", "emergencyStop"]
    failed = [line for line in log if "failed:" in line]
    assert failed and all("ERROR" in line for line in failed), failed
    assert failed[0].endswith(f"step {NAN_FROM} manip_a_cs: outputMotorCon/pf failed: "
                              "a non-finite number in motorControllerCommandK/ob")


def test_with_the_report_policy_a_nan_is_reported_and_changes_no_state(
        deployment: tuple[Path, dict[str, str]], tmp_path: Path) -> None:
    lines, log = deploy(with_policy(deployment, "report", tmp_path / "deploy"), "nan",
                        f"step {NAN_FROM + 5} manip/a.cs: i ")
    assert deployer_states(lines) == ["idle", "jointMove"]
    reports = [line for line in log if "non-finite" in line]
    assert reports and "Warning" in reports[0], reports
    assert reports[0].endswith(f"step {NAN_FROM} manip_a_cs: outputMotorCon/pf wrote a non-finite number "
                               "into motorControllerCommandK/ob (sent)")
    assert not [line for line in log if "failed:" in line]


def test_a_policy_that_is_not_one_fails_the_configuration(
        deployment: tuple[Path, dict[str, str]], tmp_path: Path) -> None:
    folder, env = with_policy(deployment, "ignore", tmp_path / "deploy")
    lines, _ = run_until(["deployer", "-l", "info", "-s", "system.ops"],
                         lambda out: any("non_finite must be error or report" in line for line in out), 60, env,
                         cwd=folder, graceful=False)
    log = (folder / "orocos.log").read_text(errors="replace")
    assert ": the property non_finite must be error or report, not 'ignore'" in log + "\n".join(lines)

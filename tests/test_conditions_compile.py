"""A condition that ``check`` accepts compiles: B005 and B008 stop every guard the C++
generator or g++ would reject.

Each row puts one condition in the guard of the sample's idle,jointMove/t (subsystem
manip/a.cs) and says which rule must stop it, or None. Then every accepted condition goes
into that guard at once (a conjunction): the generated subsystem is compiled by g++, and the
FABRIC specification of --target orocos is read by FABRIC's parser, whose logicExprToCpp
conditions g++ compiles too.
"""

from __future__ import annotations

import html
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from earl_m2t.api import check, load
from earl_m2t.cli.app import main
from earl_m2t.gen import render
from tests.diff.variants import sample_text, with_guard_body
from tests.support import fabric

TRANSITION = "manip/a.cs.fsm.idle,jointMove/t"

# manip/a.cs: manipulatorCommand/ib (jointPosSetpoint [0..1] of JointPosition {q: Real [6]},
# operationalPosSetpoint [0..1], emergencyStopCommand: Boolean), motorControllerStateK/ib [6],
# manipulatorState/ob; memory motionFinished (Boolean), currentJointPos (JointPosition),
# currentOperationalPos (OperPosition), emergencyStopCommandK [6] (Boolean), windingCurrentK [6] (Real)
CONDITIONS: list[tuple[str, str | None]] = [
    ("manipulatorState/ob.msg.motionFinished", None),
    ("manipulatorCommand/ib.msg.operationalPosSetpoint.position.x > 0.1", None),
    ("currentOperationalPos/mi.data.position.x > 0.1", None),
    ("newData(manipulatorCommand/ib)", None),
    ("newData(manipulatorCommand/ib.msg.jointPosSetpoint.q[2])", None),
    ("manipulatorCommand/ib.msg.jointPosSetpoint[0].q[5] != 0", None),
    ("currentJointPos/m.data.q[5] < 3.0", None),
    ("currentJointPos/m.data.q[1]", None),
    ("motorControllerState3/ib.msg.motorPos > 0.5", None),
    ("windingCurrent1/m == windingCurrent2/m", None),
    ("1.5e3 < windingCurrent6/m", None),
    ("any K: windingCurrentK/m > 2", None),
    ("any K: windingCurrentK/mi.data > 2", None),  # /m, /mi and /mo name the same replicated memory
    ("all K: motorControllerStateK/ib.msg.emergencyStopCommand", None),
    ("motorControllerState1/ib.msg.emergencyStopCommand ∨ … ∨ motorControllerStateN/ib.msg.emergencyStopCommand",
     None),
    ("emergencyStopCommand2/m", None),
    ("motionFinished/mo.data", None),
    ("1 < 2", None),
    ("newJointPos", None),
    ("manipulatorCommand/ib.msg.emergencyStopCommand[2]", "B005"),  # a Boolean, not an array
    ("currentJointPos/m.data.q[6] > 0.5", "B005"),  # q has 6 elements, 0 to 5
    ("manipulatorCommand/ib.msg.jointPosSetpoint[1].q[0] > 0", "B005"),  # an optional value holds 1
    ("manipulatorCommand/ib.msg.jointPosSetpoint[0].q.x > 0", "B005"),  # q is an array: index it
    ("currentJointPos/m.data.q > 0.5", "B005"),  # a whole array compared
    ("currentJointPos/m.data.q", "B005"),  # a whole array as a truth value
    ("manipulatorCommand/ib.msg.jointPosSetpoint", "B005"),  # an optional composite value
    ("manipulatorCommand/ib.msg", "B005"),  # a composite value
    ("motorControllerState7/ib.msg.motorPos > 0.5", "B005"),  # six instances
    ("windingCurrent9/m > 2", "B005"),
    ("motorControllerStateK/ib.msg.motorPos > 0", "B005"),  # the template outside a replication
    ("motionFinished/m > 0", "B005"),  # a Boolean compared
    ("newData(manipulatorState/ob.msg.motionFinished)", "B005"),  # an output buffer
    ("motorControllerState1/ib.data.motorPos > 1", "B005"),  # a buffer holds msg
    ("manipulatorCommand/ib.msg.emergencyStopCommand.x", "B005"),  # no field x
    ("newJointPos/pp.fun ∧", "B008"),
]


def with_guard(condition: str, folder: Path) -> Path:
    path = folder / "model.uml"
    path.write_text(with_guard_body(sample_text(), html.escape(condition, quote=False)), encoding="utf-8")
    return path


def guard_errors(path: Path) -> set[str]:
    return {d.code for d in check(path) if d.severity.value == "error" and d.element == TRANSITION}


@pytest.mark.parametrize(("condition", "rule"), CONDITIONS, ids=[c for c, _ in CONDITIONS])
def test_check_stops_exactly_the_conditions_that_cannot_compile(condition: str, rule: str | None,
                                                                tmp_path: Path) -> None:
    assert guard_errors(with_guard(condition, tmp_path)) == ({rule} if rule else set())


@pytest.mark.skipif(shutil.which("g++") is None, reason="g++ is not installed")
def test_every_accepted_condition_compiles(tmp_path: Path) -> None:
    accepted = [condition for condition, rule in CONDITIONS if rule is None]
    path = with_guard(" ∧ ".join(f"({c})" for c in accepted), tmp_path)
    assert guard_errors(path) == set()
    out = tmp_path / "out"
    assert main(["gen", str(path), "--target", "cpp", "-o", str(out)]) == 0
    compiled = subprocess.run(["g++", "-std=c++17", "-fsyntax-only", "-Wall", "-Wextra", "-Werror", "-Iruntime",
                               "-Igenerated/include", "-Iuser", "generated/src/manip_a_main.cpp"],
                              cwd=out, capture_output=True, text=True, env={**os.environ, "LC_ALL": "C"}, timeout=300)
    assert compiled.returncode == 0, compiled.stderr[-3000:]
    header = (out / "generated/include/PickAndPlace/manip_a/cs/subsystem.hpp").read_text(encoding="utf-8")
    assert "data_.currentJointPos_m.q[5]" in header and "jointPosSetpoint[0].q[5]" in header

    spec = tmp_path / "subsystem.xml"
    spec.write_bytes(render(load(path).model, "orocos").generated["fabric/manip_a_cs/spec/subsystem.xml"])
    parsed = fabric.parse_spec(spec)
    assert "currentJointPos_m_data_q_5_3" in parsed.predicates  # an atom of the guard, as FABRIC names it
    work = tmp_path / "fabric"
    work.mkdir()
    conditions = fabric.compile_conditions(parsed, work)
    assert conditions.returncode == 0, conditions.stderr[-3000:]


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))

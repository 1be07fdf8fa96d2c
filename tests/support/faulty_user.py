"""The pick_and_place sample's user code with faults a run switches on by the environment
variable EARL_FAULT (read once, when the pf objects are built):

- ``throw``: jointMove/pf throws ``std::runtime_error("motor driver timeout")`` when a command
  arrives (its first iteration in jointMove);
- ``fail``: jointMove/pf calls ``fail("motor driver stopped answering")`` then;
- ``nan``: outputMotorCon/pf writes NaN into motorControllerCommandK/ob (joint 3) in its runs
  NAN_FROM to NAN_UNTIL - 1 (in jointMove: that state lasts some 740 iterations).

Without EARL_FAULT the code is the sample's. Shared by the C++, ROS and Orocos runs.
"""

from __future__ import annotations

import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
USER = ROOT / "samples" / "pick_and_place" / "user"
NAN_FROM, NAN_UNTIL = 100, 110
THROWN = "motor driver timeout"
FAILED = "motor driver stopped answering"

_FAULT = '  const char* const fault_ = std::getenv("EARL_FAULT");  // test copy: the fault to inject\n'


def _edit(path: Path, replacements: list[tuple[str, str]]) -> None:
    text = path.read_text(encoding="utf-8")
    for old, new in replacements:
        assert text.count(old) == 1, f"{path.name}: {old!r} is not there once"
        text = text.replace(old, new)
    path.write_text(text, encoding="utf-8")


def copy_faulty_user(target: Path) -> Path:
    """``target`` holding the sample's user code with the faults; returns ``target``."""
    shutil.copytree(USER, target)
    cs = target / "manip_a" / "cs"
    thrown, failed, nan = (f'fault_ != nullptr && std::strcmp(fault_, "{name}") == 0'
                           for name in ("throw", "fail", "nan"))
    _edit(cs / "jointMove_pf.hpp", [
        ("#include <cmath>\n", "#include <cmath>\n#include <cstdlib>\n#include <cstring>\n#include <stdexcept>\n"),
        ("    const auto& command = manipulatorCommand_ib();\n",
         "    const auto& command = manipulatorCommand_ib();\n"
         f"    if (manipulatorCommand_ib_newData() && {thrown}) throw std::runtime_error(\"{THROWN}\");\n"
         f"    if (manipulatorCommand_ib_newData() && {failed}) {{\n"
         f"      fail(\"{FAILED}\");\n      return;\n    }}\n"),
        (" private:\n", " private:\n" + _FAULT),
    ])
    _edit(cs / "outputMotorCon_pf.hpp", [
        ("#include <cstdio>\n", "#include <cstdio>\n#include <cstdlib>\n#include <cstring>\n#include <limits>\n"),
        ("    if (trace_) {\n",
         f"    if ({nan} && step_ >= {NAN_FROM} && step_ < {NAN_UNTIL}) {{\n"
         "      motorControllerCommandK_ob(2).desiredWindingCurrent = std::numeric_limits<double>::quiet_NaN();\n"
         "    }\n    if (trace_) {\n"),
        (" private:\n", " private:\n" + _FAULT),
    ])
    return target

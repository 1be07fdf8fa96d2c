"""``gen --target cpp`` for a model with configurations (``tests/fixtures/variability/handover.sysml``):
the system's switch tables (agent and link masks per configuration, the coordinator's map from
states to configurations, reactivation), ``leaving()`` compiled to the runtime's predicate, the
switch runtime copied only for such a model; the project builds with warnings as errors and
switches at run time, deterministically.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.gen import render

ROOT = Path(__file__).resolve().parents[1]
FIXTURE = ROOT / "tests" / "fixtures" / "variability" / "handover.sysml"
PLAIN = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
SYSTEM = "generated/include/Handover/system.hpp"
MANIPULATOR = "generated/include/Handover/manipA_a/cs/subsystem.hpp"

# task/a.cs numbers its commands; handOver/pp (sent > 10) then holds in every later
# iteration, so task/a switches configuration at every iteration from the 11th on
COMMAND_PF = """// earl-m2t user file: pf task/a.cs.command/pf
#pragma once

#include "Handover/task_a/cs/data.hpp"

namespace Handover::task_a::cs {

class command_pf final : public command_pf_base {
 public:
  using command_pf_base::command_pf_base;

  void execute() noexcept override {
    sent_mo() += 1;
    command_ob().seq = sent_mo();
  }
};

}  // namespace Handover::task_a::cs
"""


@pytest.fixture(scope="module")
def files() -> dict[str, str]:
    rendered = render(load(FIXTURE).model, "cpp")
    return {path: content.decode("utf-8") for path, content in rendered.generated.items()}


def test_the_system_holds_the_configuration_tables(files: dict[str, str]) -> None:
    system = files[SYSTEM]
    assert 'kConfigurations[] = {"useA", "useB"};' in system
    assert "// 2 variable agent(s): manipA/a manipB/a" in system
    assert re.search(r"kAgentMask\[\] = \{\n\s+true, false,  // useA\n\s+false, true,  // useB\n", system)
    assert "// 4 variable link(s): task/a,manipA/a task/a,manipB/a manipA/a,task/a manipB/a,task/a" in system
    assert re.search(r"kLinkMask\[\] = \{\n\s+true, false, true, false,  // useA\n"
                     r"\s+false, true, false, true,  // useB\n", system)
    assert "kSwitchTimeoutNs[] = {50000000, 50000000};" in system
    assert "kStateConfiguration[] = {0, 1};" in system
    assert "switch_.start(0);  // useA" in system
    assert 'earl::AgentSlot slot_manipA_a{"manipA/a", earl::Reactivation::resume};' in system
    assert 'earl::switchLink("task/a,manipA/a", link_task_a_manipA_a, &slot_manipA_a)' in system
    assert 'earl::switchLink("manipA/a,task/a", link_manipA_a_task_a, nullptr)' in system  # task/a stays


def test_subsystems_follow_their_agent_and_leaving_compiles(files: dict[str, str]) -> None:
    manipulator = files[MANIPULATOR]
    assert "public earl::SwitchedSubsystem<Subsystem>" in manipulator
    assert "return (newCommand_pp() && !leaving());" in manipulator
    assert re.search(r"static const bool states\[\] = \{\n\s+true,  // idle\n\s+false,  // moving\n", manipulator)
    assert "earl::SwitchedInputPort<" in files["generated/include/Handover/manipA_a/cs/data.hpp"]
    assert "void joinSlot(earl::AgentSlot& slot) noexcept" in files["generated/include/Handover/manipA_a/agent.hpp"]
    assert "earl::SwitchPrintObserver trace;" in files["generated/src/system_main.cpp"]


def test_the_switch_runtime_comes_only_with_configurations(files: dict[str, str]) -> None:
    assert "runtime/earl/switch.hpp" in files
    plain = render(load(PLAIN).model, "cpp").generated
    assert "runtime/earl/switch.hpp" not in plain
    assert not any(b"switch.hpp" in content for content in plain.values())


@pytest.mark.skipif(shutil.which("g++") is None or shutil.which("cmake") is None, reason="g++ and cmake are needed")
def test_the_project_builds_and_switches_deterministically(tmp_path: Path) -> None:
    out, build = tmp_path / "out", tmp_path / "build"
    (out / "user" / "task_a" / "cs").mkdir(parents=True)
    (out / "user" / "task_a" / "cs" / "command_pf.hpp").write_text(COMMAND_PF, encoding="utf-8")
    for command in ([sys.executable, "-m", "earl_m2t", "gen", str(FIXTURE), "--target", "cpp", "-o", str(out)],
                    ["cmake", "-S", str(out), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                     "-DCMAKE_CXX_COMPILER=g++", "-DCMAKE_CXX_FLAGS=-Wall -Wextra -Werror"],
                    ["cmake", "--build", str(build), "-j", "2", "--target", "Handover_system"]):
        result = subprocess.run(command, capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, result.stdout + result.stderr
    runs = [subprocess.run([str(build / "Handover_system"), "--cycles", "200"], capture_output=True, text=True,
                           timeout=60).stdout.splitlines() for _ in range(2)]
    assert runs[0] == runs[1]
    switches = [line for line in runs[0] if line.startswith("switch ")]
    assert len(switches) > 20
    assert all(re.fullmatch(r"switch (useA -> useB|useB -> useA) in \d+ cycles", line) for line in switches)
    assert all(int(line.split()[-2]) <= 50 for line in switches)  # switchTimeout 0.05 s, 1 ms per cycle
    assert not [line for line in runs[0] if "undelivered" in line or "overflowed" in line]

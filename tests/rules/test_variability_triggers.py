"""Every rule of variable structure (family X), and the structural rules run per configuration,
fire on a small mutation of the hand-over fixture (tests/fixtures/variability/handover.sysml),
which itself is clean.

Each row of ``VARIABILITY_VARIANTS`` takes the fixture's text and gives the broken text, the
codes the check must report (exactly) and a text one finding of the row's rule must contain.
A mutation that breaks the structure in a way that another rule reports too (a coordinator's
agent absent leaves its links dangling) lists both codes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

from earl_m2t import Diagnostic, check
from earl_m2t.check.engine import CheckOptions

ROOT = Path(__file__).resolve().parents[2]
FIXTURE = ROOT / "tests" / "fixtures" / "variability" / "handover.sysml"

USE_A = 'metadata useA : Structure { agents = "manipA/a"; links = "task/a,manipA/a manipA/a,task/a"; '
USE_B = 'metadata useB : Structure { agents = "manipB/a"; links = "task/a,manipB/a manipB/a,task/a"; '
STOPS = '@Activation { bufferGroup = "stops"; firstTimeout = 0.01; nextTimeout = 0.01; }'
TASK_FSM_END = '''                transition 'withB,withA/t' first withB then withA {
                    language "EARL" /* handOver/pp */
                }
'''


@dataclass(frozen=True)
class Broken:
    text: str
    codes: frozenset[str]
    names: str  # a finding of the row's rule contains it


def _edit(text: str, old: str, new: str) -> str:
    assert old in text, old
    return text.replace(old, new, 1)


def _coordinator_state(text: str, name: str, configuration: str) -> str:
    """A coordinator state ``name`` naming ``configuration``, entered from withB (on a guard that is
    false whenever withB's behaviour ends, so no transitions overlap) and left for withA."""
    state = f'''                state {name} {{
                    @Reconfigure {{ configuration = "{configuration}"; }}
                    do action '{name}/bb' {{
                        first start;
                        then action command : 'command/pf';
                        then done;
                        constraint tc {{ language "EARL" /* handOver/pp */ }}
                        constraint ec {{ false }}
                    }}
                }}
                transition 'withB,{name}/t' first withB then {name} {{
                    language "EARL" /* not handOver/pp */
                }}
                transition '{name},withA/t' first {name} then withA {{
                    language "EARL" /* handOver/pp */
                }}
'''
    return _edit(text, TASK_FSM_END, TASK_FSM_END + state)


def _configuration(text: str, line: str) -> str:
    end = text.index("\n", text.index("metadata useB : Structure")) + 1
    return text[:end] + f"            {line}\n" + text[end:]


def unknown_agent(text: str) -> Broken:
    """X001: useA names manipC/a, which is no agent."""
    return Broken(_edit(text, 'agents = "manipA/a";', 'agents = "manipA/a manipC/a";'), frozenset({"X001"}),
                  "names agent 'manipC/a'")


def unknown_link(text: str) -> Broken:
    """X001: useA names the link task/a,manipC/a, which does not exist."""
    return Broken(_edit(text, 'links = "task/a,manipA/a manipA/a,task/a";',
                        'links = "task/a,manipA/a manipA/a,task/a task/a,manipC/a";'),
                  frozenset({"X001"}), "names link 'task/a,manipC/a'")


def subsystem_named(text: str) -> Broken:
    """X001: useA names the subsystem manipA/a.cs besides its agent."""
    return Broken(_edit(text, 'agents = "manipA/a";', 'agents = "manipA/a manipA/a.cs";'), frozenset({"X001"}),
                  "names subsystem manipA/a.cs")


def dangling_link(text: str) -> Broken:
    """X002: useA also names the link to manipB/a, which is absent in useA."""
    return Broken(_edit(text, 'links = "task/a,manipA/a manipA/a,task/a";',
                        'links = "task/a,manipA/a manipA/a,task/a task/a,manipB/a";'),
                  frozenset({"X002"}), "link task/a,manipB/a is present in configuration Cell.useA")


def two_coordinators(text: str) -> Broken:
    """X003: the manipulators' idle state names useA too: three subsystems switch configurations."""
    return Broken(_edit(text, "@Quiescent;", '@Quiescent; @Reconfigure { configuration = "useA"; }'),
                  frozenset({"X003"}), "3 subsystems name configurations")


def no_coordinator(text: str) -> Broken:
    """X003: no state names a configuration: nothing selects one."""
    text = _edit(text, '@Reconfigure { configuration = "useA"; }', "")
    return Broken(_edit(text, '@Reconfigure { configuration = "useB"; }', ""), frozenset({"X003"}),
                  "system Cell has configurations")


def initial_state_without_configuration(text: str) -> Broken:
    """X004: the coordinator starts in a new state starting, which names no configuration."""
    text = _edit(text, "entry; then withA;", "entry; then starting;")
    starting = '''                state starting {
                    do action 'starting/bb' {
                        first start;
                        then action command : 'command/pf';
                        then done;
                        constraint tc { language "EARL" /* handOver/pp */ }
                        constraint ec { false }
                    }
                }
                transition 'starting,withA/t' first starting then withA {
                    language "EARL" /* handOver/pp */
                }
'''
    return Broken(_edit(text, TASK_FSM_END, TASK_FSM_END + starting), frozenset({"X004"}),
                  "starts in state task/a.cs.fsm.starting")


def unknown_configuration(text: str) -> Broken:
    """X004: withB names useb (a typo), so useB is never reached (X010)."""
    return Broken(_edit(text, 'configuration = "useB";', 'configuration = "useb";'), frozenset({"X004", "X010"}),
                  "names configuration 'useb'")


def coordinator_agent_absent(text: str) -> Broken:
    """X005: useA names task/a (optional, quiescent in withA), so task/a is absent in useB, where its
    links to manipB/a dangle (X002)."""
    text = _edit(text, 'agents = "manipA/a";', 'agents = "manipA/a task/a";')
    text = _edit(text, "part 'task/a' : TaskAgent;", "part 'task/a' : TaskAgent[0..1];")
    reconfigure = '@Reconfigure { configuration = "useA"; }'
    text = _edit(text, reconfigure, reconfigure + " @Quiescent;")
    return Broken(text, frozenset({"X005", "X002"}), "agent task/a of the coordinator task/a.cs is absent")


def variable_agent_not_optional(text: str) -> Broken:
    """X006: manipA/a's part loses its multiplicity [0..1]."""
    return Broken(_edit(text, "part 'manipA/a' : ManipulatorAgent[0..1];", "part 'manipA/a' : ManipulatorAgent;"),
                  frozenset({"X006"}), "agent manipA/a is present only where")


def optional_agent_unnamed(text: str) -> Broken:
    """X006: task/a's part is [0..1], but no configuration names it."""
    return Broken(_edit(text, "part 'task/a' : TaskAgent;", "part 'task/a' : TaskAgent[0..1];"),
                  frozenset({"X006"}), "agent task/a has multiplicity [0..1]")


def obligatory_input_closed(text: str) -> Broken:
    """X007: a third configuration useAB holds both manipulators, manipB/a's links and manipA/a's
    status link only; manipA/a waits for its obligatory command/ib (no firstTimeout) with no link open."""
    text = _configuration(text, 'metadata useAB : Structure { agents = "manipA/a manipB/a"; '
                                'links = "task/a,manipB/a manipB/a,task/a manipA/a,task/a"; switchTimeout = 0.05; }')
    return Broken(_coordinator_state(text, "withAB", "useAB"), frozenset({"X007"}),
                  "no link into it is open in configuration useAB")


def _with_stops(text: str, optional: str) -> str:
    """The manipulators with an Input Buffer stop/ib, a group stops (stop/ib obligatory,
    ``optional`` optional) and a pf hold/pf that reads nothing."""
    return _edit(text, "            port 'status/ob' : OutputBuffer { attribute :>> msg : DataTypes::Status; }\n"
                       "            metadata commands",
                 "            port 'status/ob' : OutputBuffer { attribute :>> msg : DataTypes::Status; }\n"
                 "            port 'stop/ib' : InputBuffer {\n"
                 "                attribute :>> msg : DataTypes::Status;\n"
                 "                comment /* earl-m2t: ignore[C007] wired by the cell's integrator */\n"
                 "            }\n"
                 f'            metadata stops : Group {{ obligatory = "stop/ib"; optional = "{optional}"; }}\n'
                 "            action def 'hold/pf' { out 'status/ob'; language \"C++\" /* // Holds. */ }\n"
                 "            metadata commands")


def queue_not_drained(text: str) -> Broken:
    """X008: the manipulators' moving state waits for a new input stop/ib instead of command/ib, its
    behaviour calls a pf that does not read command/ib and its conditions do not read it; moving is
    not quiescent."""
    return Broken(_moving_holds(_with_stops(text, ""), STOPS), frozenset({"X008"}),
                  "does not receive its queued input manipA/a.cs.command/ib")


def _moving_holds(text: str, activation: str) -> str:
    """The manipulators' moving state with ``activation``, running hold/pf, left on leaving() only:
    nothing in it reads command/ib."""
    text = _edit(text, '''                state moving {
                    @Activation { bufferGroup = "commands"; nextTimeout = 0.01; }
                    do action 'moving/bb' {
                        first start;
                        then action follow : 'follow/pf';
                        then done;
                        constraint tc { language "EARL" /* leaving() or not newCommand/pp */ }''',
                 f'''                state moving {{
                    {activation}
                    do action 'moving/bb' {{
                        first start;
                        then action hold : 'hold/pf';
                        then done;
                        constraint tc {{ language "EARL" /* leaving() */ }}''')
    return _edit(text, "/* leaving() or not newCommand/pp */\n                }\n            }",
                 "/* leaving() */\n                }\n            }")


def queue_optional_not_drained(text: str) -> Broken:
    """X008: as X008, but moving's group names command/ib optional: an optional input the behaviour
    never reads is not received (earl_m2t.analysis.receiving), so the queue waits there."""
    return Broken(_moving_holds(_with_stops(text, "command/ib"), STOPS), frozenset({"X008"}),
                  "does not receive its queued input manipA/a.cs.command/ib")


def queue_not_drained_periodic(text: str) -> Broken:
    """X008: the manipulators run on their period (no buffer groups) and moving's behaviour reads
    nothing of command/ib: a state without a group receives what its behaviour reads, not every
    input."""
    text = _edit(text, "            metadata commands",
                 "            action def 'hold/pf' { out 'status/ob'; language \"C++\" /* // Holds. */ }\n"
                 "            metadata commands")
    text = _edit(text, '            metadata commands : Group { obligatory = "command/ib"; optional = ""; }\n', "")
    text = _edit(text, '                    @Activation { bufferGroup = "commands"; nextTimeout = 0.01; }\n'
                       "                    do action 'idle/bb'", "                    do action 'idle/bb'")
    return Broken(_moving_holds(text, "// on the subsystem's period"), frozenset({"X008"}),
                  "does not receive its queued input manipA/a.cs.command/ib")


def write_on_closed_links(text: str) -> Broken:
    """X014: with a command buffer per manipulator, withA (useA: manipA/a's link only) sends on
    commandB/ob, whose one link useA closes."""
    text = _command_per_manipulator(text)
    text = _edit(text, "then action command : 'commandA/pf';", "then action command : 'commandB/pf';")
    return Broken(text, frozenset({"X014", "T006"}), "writes Output Buffer task/a.cs.commandB/ob, but "
                  "configuration useA")


def switch_timeout_short(text: str) -> Broken:
    """X009: the manipulators iterate at most every 2 ms (minPeriod), so draining 32 queued commands
    takes 64 ms, longer than the 50 ms switchTimeout."""
    text = text.replace("nextTimeout = 0.01; }", "minPeriod = 0.002; nextTimeout = 0.01; }")
    return Broken(text, frozenset({"X009"}), "32 values × 0.002 s + 0 s (a coordinator period) = 0.064 s")


def unreachable_configuration(text: str) -> Broken:
    """X010: a configuration spare, alike useB, that no coordinator state names."""
    return Broken(_configuration(text, USE_B.replace("useB", "spare") + "switchTimeout = 0.05; }"),
                  frozenset({"X010"}), "configuration Cell.spare is named by no state")


def duplicate_configuration(text: str) -> Broken:
    """X010: a state withSpare names spare, a configuration alike useB."""
    text = _configuration(text, USE_B.replace("useB", "spare") + "switchTimeout = 0.05; }")
    return Broken(_coordinator_state(text, "withSpare", "spare"), frozenset({"X010"}),
                  "has the same agents and links as Cell.useB")


def leaving_in_fixed_agent(text: str) -> Broken:
    """X011: the coordinator's guard withA,withB/t also tests leaving(), always false in task/a."""
    guard = 'first withA then withB {\n                    language "EARL" /* handOver/pp'
    return Broken(_edit(text, guard + " */", guard + " or leaving() */"),
                  frozenset({"X011"}), "uses leaving(), which is always false in task/a.cs")


def reactivation_unknown(text: str) -> Broken:
    """X012: the manipulators' reactivation is reboot."""
    return Broken(_edit(text, "reactivation = Reactivation::resume;", "reactivation = Reactivation::reboot;"),
                  frozenset({"X012"}), "has reactivation 'reboot'")


def switch_timeout_negative(text: str) -> Broken:
    """X012: useA's switchTimeout is negative."""
    return Broken(_edit(text, "task/a,manipA/a manipA/a,task/a\"; switchTimeout = 0.05;",
                        "task/a,manipA/a manipA/a,task/a\"; switchTimeout = -0.05;"),
                  frozenset({"X012"}), "switchTimeout is not a number of seconds > 0")


def no_quiescent_state(text: str) -> Broken:
    """X013: the manipulators declare no quiescent state."""
    return Broken(_edit(text, "@Quiescent;", ""), frozenset({"X013"}), "has no quiescent state")


def quiescent_in_fixed_agent(text: str) -> Broken:
    """X013: the coordinator's withA is quiescent, but no configuration removes task/a."""
    return Broken(_edit(text, '@Reconfigure { configuration = "useA"; }',
                        '@Reconfigure { configuration = "useA"; } @Quiescent;'),
                  frozenset({"X013"}), "state task/a.cs.fsm.withA is quiescent")


def robot_empty_in_configuration(text: str) -> Broken:
    """S002: a configuration parked holds no manipulator: robot cell/r has no agent there, and task/a
    has no link (S006)."""
    text = _configuration(text, 'metadata parked : Structure { agents = ""; links = ""; switchTimeout = 0.05; }')
    return Broken(_coordinator_state(text, "waiting", "parked"), frozenset({"S002", "S006", "X014"}),
                  "[configuration parked] robot cell/r contains no agent")


def zombie_in_configuration(text: str) -> Broken:
    """S006: in the configuration parked task/a has no inter-agent link (and cell/r no agent, S002)."""
    broken = robot_empty_in_configuration(text)
    return Broken(broken.text, broken.codes, "[configuration parked] agent task/a is a zombie")


ARM = '''
        part def ArmDriver :> VirtualEffector {
            port 'joint/ib' : InputBuffer { attribute :>> msg : DataTypes::Command; }
            port 'current/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }
            action def 'drive/pf' { in 'joint/ib'; out 'current/ob'; language "C++" /* // Drives. */ }
            state fsm {
                entry; then drive;
                state drive {
                    do action 'drive/bb' {
                        first start;
                        then action drive : 'drive/pf';
                        then done;
                        constraint tc { false }
                        constraint ec { false }
                    }
                }
            }
        }

        part def ArmMotor :> RealEffector {
            port 'current/ib' : InputBuffer { attribute :>> msg : DataTypes::Command; }
            action def 'apply/pf' { in 'current/ib'; language "C++" /* // Applies the current. */ }
            state fsm {
                entry; then apply;
                state apply {
                    do action 'apply/bb' {
                        first start;
                        then action apply : 'apply/pf';
                        then done;
                        constraint tc { false }
                        constraint ec { false }
                    }
                }
            }
        }
'''


def effector_chain_cut_in_configuration(text: str) -> Broken:
    """C004: the manipulators get an arm (arm/ve, arm/re); manipA/a's link cs,arm/ve is named by useA
    only, and a third configuration useAB, which holds manipA/a, leaves it out: arm/re is not reached
    there."""
    text = _edit(text, "            part cs : ManipulatorControl;\n", '''            part cs : ManipulatorControl;
            part 'arm/ve' : ArmDriver;
            part 'arm/re' : ArmMotor;
            interface 'cs,arm/ve' : InterSubsystemLink connect cs.'joint/ob' to 'arm/ve'.'joint/ib';
            interface 'arm/ve,arm/re' : InterSubsystemLink connect 'arm/ve'.'current/ob' to 'arm/re'.'current/ib';
''')
    text = _edit(text, "            port 'status/ob' : OutputBuffer { attribute :>> msg : DataTypes::Status; }\n",
                 "            port 'status/ob' : OutputBuffer { attribute :>> msg : DataTypes::Status; }\n"
                 "            port 'joint/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n")
    writes = "                out 'status/ob';\n"
    text = _edit(text, writes, writes + "                out 'joint/ob';\n")
    task = "        part def TaskAgent :> Agent {"
    text = _edit(text, task, ARM.lstrip("\n") + "\n" + task)
    for agent in ("manipA/a", "manipB/a"):
        links = f'links = "task/a,{agent} {agent},task/a'
        text = _edit(text, links + '";', f'{links} {agent}.cs,arm/ve";')
    text = _configuration(text, 'metadata useAB : Structure { agents = "manipA/a manipB/a"; '
                                'links = "task/a,manipB/a manipB/a,task/a manipB/a.cs,arm/ve task/a,manipA/a '
                                'manipA/a,task/a"; switchTimeout = 0.05; }')
    return Broken(_coordinator_state(text, "withAB", "useAB"), frozenset({"C004"}),
                  "[configuration useAB] real effector manipA/a.arm/re is not reached")


def effector_coordinator(text: str) -> Broken:
    """X003: task/a gets an arm (arm/ve, arm/re) whose virtual effector's only state names useA; the
    control subsystem's states name none: the one coordinator is not a control subsystem."""
    text = _edit(text, "            part cs : TaskControl;\n", '''            part cs : TaskControl;
            part 'arm/ve' : ArmDriver;
            part 'arm/re' : ArmMotor;
            interface 'cs,arm/ve' : InterSubsystemLink connect cs.'joint/ob' to 'arm/ve'.'joint/ib';
            interface 'arm/ve,arm/re' : InterSubsystemLink connect 'arm/ve'.'current/ob' to 'arm/re'.'current/ib';
''')
    text = _edit(text, "            port 'command/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n",
                 "            port 'command/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n"
                 "            port 'joint/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n")
    writes = "                out 'sent/mo';\n"
    text = _edit(text, writes, writes + "                out 'joint/ob';\n")
    task = "        part def TaskAgent :> Agent {"
    reconfigure_a = '@Reconfigure { configuration = "useA"; }'
    text = _edit(text, task, ARM.lstrip("\n").replace("state drive {", "state drive { " + reconfigure_a) + "\n" + task)
    with_a = "\n                    do action 'withA/bb'"
    text = _edit(text, reconfigure_a + with_a, with_a)
    text = _edit(text, '@Reconfigure { configuration = "useB"; }', "")
    return Broken(text, frozenset({"X003"}), "subsystem task/a.arm/ve (ve) names configurations")


VARIABILITY_VARIANTS: dict[str, Callable[[str], Broken]] = {
    "X001": unknown_agent,
    "X001-link": unknown_link,
    "X001-subsystem": subsystem_named,
    "X002": dangling_link,
    "X003": two_coordinators,
    "X003-none": no_coordinator,
    "X003-not-control": effector_coordinator,
    "X004": initial_state_without_configuration,
    "X004-unknown": unknown_configuration,
    "X005": coordinator_agent_absent,
    "X006": variable_agent_not_optional,
    "X006-unnamed": optional_agent_unnamed,
    "X007": obligatory_input_closed,
    "X008": queue_not_drained,
    "X008-optional": queue_optional_not_drained,
    "X008-periodic": queue_not_drained_periodic,
    "X009": switch_timeout_short,
    "X010": unreachable_configuration,
    "X010-duplicate": duplicate_configuration,
    "X011": leaving_in_fixed_agent,
    "X012": reactivation_unknown,
    "X012-timeout": switch_timeout_negative,
    "X013": no_quiescent_state,
    "X014": write_on_closed_links,
    "X013-fixed-agent": quiescent_in_fixed_agent,
    "S002-configuration": robot_empty_in_configuration,
    "S006-configuration": zombie_in_configuration,
    "C004-configuration": effector_chain_cut_in_configuration,
}


def _describe(findings: list[Diagnostic]) -> str:
    return "\n".join(f"  {d.code} {d.location.line} {d.message}" for d in findings) or "  (none)"


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "variant.sysml"
    path.write_text(text, encoding="utf-8")
    return path


def test_fixture_is_clean() -> None:
    findings = check(FIXTURE)
    assert findings == [], _describe(findings)


def test_every_mutation_says_what_it_breaks() -> None:
    for variant, mutation in VARIABILITY_VARIANTS.items():
        assert (mutation.__doc__ or "").startswith(variant.partition("-")[0]), mutation.__name__


@pytest.mark.parametrize("variant", list(VARIABILITY_VARIANTS))
def test_variant_triggers_its_rule(variant: str, tmp_path: Path) -> None:
    code = variant.partition("-")[0]
    broken = VARIABILITY_VARIANTS[variant](FIXTURE.read_text(encoding="utf-8"))
    findings = check(_write(tmp_path, broken.text))
    assert {d.code for d in findings} == broken.codes, _describe(findings)
    assert any(d.code == code and broken.names in d.message and d.location.line > 0 for d in findings), (
        _describe(findings))


def test_a_rule_per_configuration_is_ignored_by_its_code(tmp_path: Path) -> None:
    path = _write(tmp_path, robot_empty_in_configuration(FIXTURE.read_text(encoding="utf-8")).text)
    findings = check(path, CheckOptions(ignore=frozenset({"S006"})))
    assert {d.code for d in findings} == {"S002", "X014"}, _describe(findings)



def _command_per_manipulator(text: str) -> str:
    """The task with an Output Buffer per manipulator (commandA/ob linked to manipA/a, commandB/ob
    to manipB/a), withA writing only commandA/ob and withB only commandB/ob."""
    text = _edit(text, "connect 'task/a'.cs.'command/ob' to 'cell/r'.'manipA/a'",
                 "connect 'task/a'.cs.'commandA/ob' to 'cell/r'.'manipA/a'")
    text = _edit(text, "connect 'task/a'.cs.'command/ob' to 'cell/r'.'manipB/a'",
                 "connect 'task/a'.cs.'commandB/ob' to 'cell/r'.'manipB/a'")
    text = _edit(text, "            port 'command/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n",
                 "            port 'commandA/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n"
                 "            port 'commandB/ob' : OutputBuffer { attribute :>> msg : DataTypes::Command; }\n")
    pf = text[text.index("            action def 'command/pf' {"):]
    pf = pf[:pf.index("            }\n") + len("            }\n")]
    text = _edit(text, pf, pf.replace("'command/pf'", "'commandA/pf'").replace("'command/ob'", "'commandA/ob'")
                 + pf.replace("'command/pf'", "'commandB/pf'").replace("'command/ob'", "'commandB/ob'"))
    text = _edit(text, "then action command : 'command/pf';", "then action command : 'commandA/pf';")
    return _edit(text, "then action command : 'command/pf';", "then action command : 'commandB/pf';")


def test_an_output_whose_links_the_configuration_closes_is_not_stale(tmp_path: Path) -> None:
    """T006 knows the configurations: withA never writes commandB/ob, whose one link useA (the only
    configuration withA can run in) closes, so nothing stale is sent; the same buffer left
    unwritten in a state where its link is open is still reported."""
    text = _command_per_manipulator(FIXTURE.read_text(encoding="utf-8"))
    findings = check(_write(tmp_path, text))
    assert findings == [], _describe(findings)
    # withB's link to manipB/a is open in useB: withB writing commandA/pf's buffer leaves commandB/ob stale
    text = text.replace("then action command : 'commandB/pf';", "then action command : 'commandA/pf';")
    findings = check(_write(tmp_path, text))
    assert [(d.code, "commandB/ob" in d.message and "withB/bb" in d.message) for d in findings
            if d.code == "T006"] == [("T006", True)], _describe(findings)
    assert {d.code for d in findings} == {"T006", "X014"}, _describe(findings)  # and withB sends on commandA/ob

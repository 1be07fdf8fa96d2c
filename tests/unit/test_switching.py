"""The analyses behind the rules of variable structure, on the hand-over fixture."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t import load
from earl_m2t.analysis.switching import (
    configurations_while,
    drain_bound,
    holding,
    induced_model,
    leaving_agents,
    reachable_configurations,
    receives,
)
from earl_m2t.model.elements import EarlModel, Subsystem
from earl_m2t.model.variability import present

ROOT = Path(__file__).resolve().parents[2]
FIXTURE = ROOT / "tests" / "fixtures" / "variability" / "handover.sysml"
PAUSE = '''                state pause {
                    do action 'pause/bb' {
                        first start;
                        then action command : 'command/pf';
                        then done;
                        constraint tc { language "EARL" /* handOver/pp */ }
                        constraint ec { false }
                    }
                }
                transition 'withA,pause/t' first withA then pause { language "EARL" /* not handOver/pp */ }
                transition 'withB,pause/t' first withB then pause { language "EARL" /* not handOver/pp */ }
                transition 'pause,withA/t' first pause then withA { language "EARL" /* handOver/pp */ }
'''


def fixture(tmp_path: Path | None = None, edit: tuple[str, str] | None = None) -> EarlModel:
    """The fixture, or in ``tmp_path`` the fixture with ``edit`` (old, new) made."""
    if tmp_path is None or edit is None:
        return load(FIXTURE).model
    text = FIXTURE.read_text(encoding="utf-8")
    assert edit[0] in text
    path = tmp_path / "edited.sysml"
    path.write_text(text.replace(edit[0], edit[1], 1), encoding="utf-8")
    return load(path).model


def sub(model: EarlModel, path: str) -> Subsystem:
    found = model.subsystem(path)
    assert found is not None
    return found


def test_a_coordinator_state_holds_the_configuration_it_names() -> None:
    assert holding(sub(fixture(), "task/a.cs")) == {"withA": {"useA"}, "withB": {"useB"}}


def test_a_state_naming_none_keeps_the_configurations_it_is_entered_with(tmp_path: Path) -> None:
    anchor = "                transition 'withA,withB/t'"
    model = fixture(tmp_path, (anchor, PAUSE + anchor))
    task = sub(model, "task/a.cs")
    assert holding(task)["pause"] == {"useA", "useB"}
    assert task.fsm is not None
    pause = task.fsm.state("pause")
    assert pause is not None
    assert [c.name for c in configurations_while(model, model.systems[0], task, pause)] == ["useA", "useB"]


def test_a_subsystem_of_a_variable_agent_runs_in_the_configurations_holding_its_agent() -> None:
    model = fixture()
    manip = sub(model, "manipB/a.cs")
    assert manip.fsm is not None
    assert [c.name for c in configurations_while(model, model.systems[0], manip, manip.fsm.states[0])] == ["useB"]
    assert [c.name for c in reachable_configurations(model, model.systems[0])] == ["useA", "useB"]
    assert [a.path for a in leaving_agents(model.systems[0])] == ["manipA/a", "manipB/a"]


def test_the_induced_model_holds_what_is_present_and_types_agents_by_their_present_links() -> None:
    model = fixture()
    system = model.systems[0]
    use_a = system.configurations[0]
    induced = induced_model(model, system, use_a)
    assert [a.path for a in induced.agents] == ["manipA/a", "task/a"]
    assert [r.agents for r in induced.robots] == [("manipA/a",)]
    assert {link.path for link in induced.links} == set(present(system, use_a).links)
    assert {a.path: a.computed_type for a in induced.agents} == {"manipA/a": "CT", "task/a": "CT"}


def test_a_state_whose_group_names_a_buffer_receives_it() -> None:
    manip = sub(fixture(), "manipA/a.cs")
    assert manip.fsm is not None
    assert all(receives(manip, state, manip.inputs[0]) for state in manip.fsm.states)


def test_the_drain_bound_needs_a_minimal_period(tmp_path: Path) -> None:
    model = fixture()
    manip = sub(model, "manipA/a.cs")
    assert drain_bound(model, manip, manip.inputs[0]) is None
    idle = "\n                    do action 'idle"
    model = fixture(tmp_path, ('@Activation { bufferGroup = "commands"; nextTimeout = 0.01; }' + idle,
                               '@Activation { bufferGroup = "commands"; minPeriod = 0.002; }' + idle))
    manip = sub(model, "manipA/a.cs")
    bound = drain_bound(model, manip, manip.inputs[0])
    assert bound is not None
    assert (bound.queue_size, bound.receiver_period, bound.coordinator_period) == (32, 0.002, 0.0)
    assert bound.seconds == pytest.approx(0.064)

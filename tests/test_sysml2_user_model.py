"""A small agent written in SysML v2 text from the documentation alone
(``tests/fixtures/sysml2/thermostat.sysml``): it reads, checks clean and has the structure
its text declares."""

from __future__ import annotations

from pathlib import Path

from earl_m2t.api import check, load

MODEL = Path(__file__).resolve().parent / "fixtures" / "sysml2" / "thermostat.sysml"


def test_the_thermostat_checks_clean() -> None:
    assert [str(d) for d in check(MODEL)] == []


def test_the_thermostat_has_the_declared_structure() -> None:
    model = load(MODEL).model
    (system,) = model.systems
    assert system.name == "Home" and [r.name for r in system.robots] == ["heating/r"]
    (agent,) = system.agents
    assert (agent.name, agent.declared_type, agent.computed_type) == ("thermostat/a", "CE", "CE")
    assert [(s.name, s.kind, s.block) for s in agent.subsystems] == [
        ("cs", "cs", "ThermostatControl"), ("heaterDriver/ve", "ve", "HeaterDriver"), ("heater/re", "re", "Heater")]
    assert [(link.name, link.source, link.target) for link in agent.links] == [
        ("cs,heaterDriver/ve", "thermostat/a.cs.heaterCommand/ob", "thermostat/a.heaterDriver/ve.command/ib"),
        ("heaterDriver/ve,heater/re", "thermostat/a.heaterDriver/ve.power/ob", "thermostat/a.heater/re.power/ib"),
    ]
    cs = agent.subsystems[0]
    assert [b.datatype for b in cs.outputs] == ["DataTypes::HeaterCommand"]
    assert [(m.name, m.datatype) for m in cs.memory] == [("temperature/m", "Real")]
    assert cs.fsm is not None and cs.fsm.initial == "off"
    assert [(t.name, t.source, t.target, t.condition.text if t.condition else None) for t in cs.fsm.transitions] == [
        ("off,on/t", "off", "on", "tooCold/pp.fun"), ("on,off/t", "on", "off", "¬tooCold/pp.fun")]
    off = cs.behaviour("off/bb")
    assert off is not None and off.stages == (("measure/pf",), ("command/pf",))
    assert off.tc is not None and off.tc.text == "tooCold/pp.fun"
    assert [(p.name, p.fun.text if p.fun else None) for p in cs.predicates] == [
        ("tooCold/pp", "temperature/mi.data < 19.5")]
    command = cs.function("command/pf")
    assert command is not None and command.language == "C++"
    assert command.reads == ("thermostat/a.cs.temperature/m",)
    assert command.writes == ("thermostat/a.cs.heaterCommand/ob",)


"""Primitive predicates as LTL atoms (``agent/subsystem.name/pp``) with the real SPIN."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.cli.app import main
from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.location import Location
from earl_m2t.verify.outcomes import state_outcomes
from earl_m2t.verify.promela import translate

ROOT = Path(__file__).resolve().parents[1]
SAMPLE_UML = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
SAMPLE_SYSML = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"


def _verify(path: Path, capsys: pytest.CaptureFixture[str], *ltl: str) -> tuple[int, dict]:
    code = main(["verify", str(path), "--format", "json", *(a for f in ltl for a in ("--ltl", f))])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("sample", [SAMPLE_UML, SAMPLE_SYSML], ids=["papyrus", "sysml"])
def test_the_exclusion_holds_of_the_predicates_latest_values(sample: Path, capsys: pytest.CaptureFixture[str]) -> None:
    both = "[] ! (manip/a.cs.newJointPos/pp && manip/a.cs.newOperationalPos/pp)"
    code, result = _verify(sample, capsys, both)
    assert code == 0, result
    assert f"{both} holds" in result["proven"]


def test_an_emergency_stop_seen_by_manip_leads_to_its_state(capsys: pytest.CaptureFixture[str]) -> None:
    """In every state but emergencyStop a true emergencyStop/pp ends the behaviour and wins."""
    prop = "[] (manip/a.cs.emergencyStop/pp -> manip/a.cs@emergencyStop)"
    code, result = _verify(SAMPLE_UML, capsys, prop)
    assert code == 0, result
    assert f"{prop} holds" in result["proven"]


def test_a_failing_predicate_property_shows_the_values_in_its_counterexample(
        capsys: pytest.CaptureFixture[str]) -> None:
    code, result = _verify(SAMPLE_UML, capsys, "[] ! manip/a.cs.emergencyStop/pp")
    assert code == 1
    (finding,) = result["findings"]
    assert finding["code"] == "V005"
    last = finding["trace"][-1]
    assert last["subsystem"] == "manip/a.cs" and last["to"] == "emergencyStop"
    assert last["values"]["emergencyStop"] is True
    # before the last step manip/a.cs never saw the emergency stop
    assert all(s["values"].get("emergencyStop") is not True for s in finding["trace"][:-1]
               if s["subsystem"] == "manip/a.cs")


def test_the_predicate_and_the_state_of_one_name_are_told_apart(capsys: pytest.CaptureFixture[str]) -> None:
    """emergencyStop/pp may hold again in emergencyStop's own iterations, or not: it is not the state."""
    code, result = _verify(SAMPLE_UML, capsys,
                           "[] (manip/a.cs@emergencyStop -> [] manip/a.cs.emergencyStop/pp)")
    assert code == 1
    (finding,) = result["findings"]
    assert finding["trace"][-1]["values"]["emergencyStop"] is False


def test_an_unknown_predicate_is_one_line_with_its_column(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", str(SAMPLE_UML), "--ltl", "[] (manip/a.cs@idle || manip/a.cs.stop/pp)"])
    err = capsys.readouterr().err
    assert code == 2
    assert err == ("earl-m2t: verify: --ltl:1:24: no primitive predicate stop/pp of the subsystem manip/a.cs "
                   "(it has: emergencyStop/pp, motionFinished/pp, newJointPos/pp, newOperationalPos/pp, "
                   "false/pp)\n")


def test_a_predicate_of_an_unknown_subsystem_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", str(SAMPLE_UML), "--ltl", "<> manip/b.cs.emergencyStop/pp"])
    assert code == 2
    assert capsys.readouterr().err == ("earl-m2t: verify: --ltl:1:4: no subsystem manip/b.cs "
                                       "(for its predicate emergencyStop/pp)\n")


def test_only_properties_over_predicates_record_them() -> None:
    model = load(SAMPLE_UML).model
    states_only = LtlProperty("p", "[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)", Location("t", 1, 1))
    over_predicate = LtlProperty("q", "<> manip/a.cs.motionFinished/pp", Location("t", 1, 1))

    assert "bool pp" not in translate(model).text
    assert "bool pp" not in translate(model, (states_only,)).text
    spec = translate(model, (over_predicate,))
    assert "bool pp0 = false; /* manip/a.cs motionFinished/pp in its latest iteration */" in spec.text
    assert spec.formulas["q"] == "<> pp0"


def test_in_error_is_the_value_of_ec_and_behaviour_ok_is_free() -> None:
    """The sample's jointMove/bb ends on ec = ¬behaviourOk(): every outcome where a pf failed
    takes jointMove,emergencyStop/t (guard emergencyStop/pp ∨ inError()), none goes back to
    idle on it, and a failure can happen (behaviourOk() takes either value)."""
    model = load(SAMPLE_SYSML).model
    [manip] = [s for s in model.subsystems if s.path == "manip/a.cs"]
    [joint_move] = [so for so in state_outcomes(model, manip) if so.state.name == "jointMove"]
    assert joint_move.exact
    failed = [o for o in joint_move.outcomes if dict(o.witness)["behaviourOk()"] is False]
    assert failed
    assert all(o.ended and o.transition is not None and o.transition.name == "jointMove,emergencyStop/t"
               for o in failed)
    assert all(dict(o.witness)["inError()"] is True for o in failed)


def test_a_model_using_in_error_and_behaviour_ok_is_verified_by_spin(capsys: pytest.CaptureFixture[str]) -> None:
    """SPIN accepts the Promela of the sample, whose conditions read both built-ins."""
    prop = "[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)"
    code, result = _verify(SAMPLE_SYSML, capsys, prop)
    assert code == 0, result
    assert f"{prop} holds" in result["proven"]

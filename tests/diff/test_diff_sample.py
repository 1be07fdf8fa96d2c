"""``earl-m2t diff`` on the reference sample and one-edit variants of it: the EARL changes,
exit codes like ``diff``, and tool noise (ids, layout, dialect) that is no change."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.diff import diff_models
from earl_m2t.diff.formats import to_text
from earl_m2t.model.elements import Activation, BufferGroup, EarlModel, Subsystem
from tests.diff import variants
from tests.diff.variants import ROOT, SAMPLE, SAMPLES


def earl(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120)


def diff_text(tmp_path: Path, edit: str) -> str:
    variant = variants.write(tmp_path, f"{edit}.uml", getattr(variants, edit)(variants.sample_text()))
    result = earl("diff", str(SAMPLE), str(variant))
    assert result.returncode == 1, result.stdout + result.stderr
    assert result.stderr == ""
    return result.stdout


def test_renamed_state_is_a_rename_and_its_transitions_follow(tmp_path: Path) -> None:
    assert diff_text(tmp_path, "renamed_state") == """\
changed  FSM manip/a.cs.fsm
           initial state: idle → waiting
renamed  state manip/a.cs.fsm.idle → manip/a.cs.fsm.waiting
changed  transition manip/a.cs.fsm.idle,jointMove/t
           source: idle → waiting
changed  transition manip/a.cs.fsm.idle,operationalMove/t
           source: idle → waiting
changed  transition manip/a.cs.fsm.jointMove,idle/t
           target: idle → waiting
changed  transition manip/a.cs.fsm.operationalMove,idle/t
           target: idle → waiting
changed  transition manip/a.cs.fsm.idle,emergencyStop/t
           source: idle → waiting
"""


def test_changed_guard_shows_the_condition_before_and_after(tmp_path: Path) -> None:
    assert diff_text(tmp_path, "changed_guard") == """\
changed  transition manip/a.cs.fsm.idle,jointMove/t
           condition: newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun → newJointPos/pp.fun
"""


def test_a_changed_ltl_property_shows_the_formula_before_and_after(tmp_path: Path) -> None:
    """A review must see a weakened safety property, though no EARL element changed."""
    assert diff_text(tmp_path, "weakened_property") == """\
changed  LTL property estopLatches
           formula: [] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop) → [] (manip/a.cs@emergencyStop -> <> manip/a.cs@idle)
"""


def test_an_ltl_property_added_as_a_comment_is_an_addition(tmp_path: Path) -> None:
    assert diff_text(tmp_path, "property_comment_added") == """\
added    LTL property taskSettles
           formula: <> task/a.cs@supervise
"""


def test_changed_priority(tmp_path: Path) -> None:
    assert diff_text(tmp_path, "changed_priority") == """\
changed  transition manip/a.cs.fsm.idle,emergencyStop/t
           priority: 2 → 3
"""


def test_added_link_names_its_ends(tmp_path: Path) -> None:
    assert diff_text(tmp_path, "added_link") == """\
added    link grip/a.commandCopy
           source: grip/a.cs.fingerCommand/ob
           target: grip/a.fingerController/ve.motorControllerCommand/ib
"""


def test_removed_subsystem_with_what_it_held_and_its_links(tmp_path: Path) -> None:
    lines = diff_text(tmp_path, "removed_subsystem").splitlines()
    assert lines[0] == ("removed  virtual effector grip/a.fingerController/ve (with 2 input buffers, 2 output buffers, "
                        "2 memories, 1 FSM, 1 state, 1 basic behaviour, 1 pf, 6 accesses)")
    assert [line for line in lines if line.startswith("removed  link")] == [
        "removed  link grip/a.cs,fingerController/ve", "removed  link grip/a.fingerController/ve,cs",
        "removed  link grip/a.fingerController/ve,fingerMotor/re",
        "removed  link grip/a.fingerMotor/re,fingerController/ve"]
    assert len([line for line in lines if not line.startswith(" ")]) == 5


def test_new_ids_and_layout_are_no_change(tmp_path: Path) -> None:
    text = variants.sample_text()
    resaved = variants.resaved(text)
    assert resaved != text and "_rXzUTEyiuXPwTQS62wjGBA" not in resaved
    result = earl("diff", str(SAMPLE), str(variants.write(tmp_path, "resaved.uml", resaved)))
    assert (result.returncode, result.stdout, result.stderr) == (0, "", "")


def test_a_rename_with_new_ids_is_a_removal_and_an_addition(tmp_path: Path) -> None:
    """Without a common id nothing says it is the same state."""
    variant = variants.write(tmp_path, "both.uml", variants.resaved(variants.renamed_state(variants.sample_text())))
    lines = earl("diff", str(SAMPLE), str(variant)).stdout.splitlines()
    assert "added    state manip/a.cs.fsm.waiting" in lines
    assert "removed  state manip/a.cs.fsm.idle" in lines


@pytest.mark.parametrize("other", ["pick_and_place.cameo.xmi", "pick_and_place.ea.xml", "pick_and_place.sysml"])
def test_the_dialects_of_the_sample_diff_as_equal(other: str) -> None:
    result = earl("diff", str(SAMPLE), str(SAMPLES / other))
    assert (result.returncode, result.stdout, result.stderr) == (0, "", "")


def test_an_ea_export_against_an_edited_papyrus_model_shows_only_the_edit(tmp_path: Path) -> None:
    variant = variants.write(tmp_path, "guard.uml", variants.changed_guard(variants.sample_text()))
    result = earl("diff", str(SAMPLES / "pick_and_place.ea.xml"), str(variant))
    assert result.returncode == 1
    assert result.stdout.splitlines()[0] == "changed  transition manip/a.cs.fsm.idle,jointMove/t"
    assert len(result.stdout.splitlines()) == 2


def test_unreadable_input_exits_2_in_one_line(tmp_path: Path) -> None:
    result = earl("diff", str(SAMPLE), str(ROOT / "README.md"))
    assert result.returncode == 2
    assert result.stdout == ""
    assert len(result.stderr.splitlines()) == 1 and "README.md:1: error:" in result.stderr
    missing = earl("diff", str(SAMPLE), str(tmp_path / "missing.uml"))
    assert missing.returncode == 2 and len(missing.stderr.splitlines()) == 1


def test_markdown_is_a_table_for_a_pull_request(tmp_path: Path) -> None:
    variant = variants.write(tmp_path, "guard.uml", variants.changed_priority(variants.changed_guard(
        variants.sample_text())))
    result = earl("diff", "--format", "markdown", "samples/pick_and_place/pick_and_place.uml", str(variant))
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert lines[0] == "### EARL model changes"
    assert lines[2].endswith(": 2 changed")
    assert "| change | element | details |" in lines
    assert ("| changed | transition `manip/a.cs.fsm.idle,jointMove/t` | condition: "
            "`newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun` → `newJointPos/pp.fun` |") in lines


def test_json_document(tmp_path: Path) -> None:
    variant = variants.write(tmp_path, "state.uml", variants.renamed_state(variants.sample_text()))
    result = earl("diff", "--format", "json", str(SAMPLE), str(variant))
    assert result.returncode == 1
    document = json.loads(result.stdout)
    assert document["format"] == 1 and document["equal"] is False
    assert document["summary"] == {"renamed": 1, "changed": 6, "added": 0, "removed": 0}
    rename = document["changes"][1]
    assert rename == {"change": "renamed", "kind": "state", "path": "manip/a.cs.fsm.waiting",
                      "old_path": "manip/a.cs.fsm.idle", "xmi_id": "_rXzUTEyiuXPwTQS62wjGBA",
                      "where": rename["where"], "instances": 1, "fields": [], "contents": {}}
    text = variant.read_text(encoding="utf-8")
    line = text.count("\n", 0, text.index('xmi:id="_rXzUTEyiuXPwTQS62wjGBA"')) + 1
    assert rename["where"].endswith(f"state.uml:{line}")


def _with_subsystem(model: EarlModel, path: str, change: object) -> EarlModel:
    """``model`` with the subsystem at ``path`` replaced by ``change(subsystem)``."""
    system = model.systems[0]
    agents = tuple(replace(a, subsystems=tuple(change(s) if s.path == path else s  # type: ignore[operator]
                                               for s in a.subsystems)) for a in system.agents)
    return replace(model, systems=(replace(system, agents=agents),))


def test_activation_settings_are_compared_field_by_field() -> None:
    """Buffer groups, a state's activation and an input's receive mode, set on the lifted model
    as the readers set them, from the sample with manip/a.cs's own activation taken out."""

    def deactivate(sub: Subsystem) -> Subsystem:
        fsm = sub.fsm
        assert fsm is not None
        states = tuple(replace(s, activation=Activation()) for s in fsm.states)
        inputs = tuple(replace(b, receive="latest", queue_size=0) for b in sub.inputs)
        return replace(sub, fsm=replace(fsm, states=states), inputs=inputs, buffer_groups=())

    model = _with_subsystem(load(SAMPLE).model, "manip/a.cs", deactivate)

    def activate(sub: Subsystem) -> Subsystem:
        fsm = sub.fsm
        assert fsm is not None
        states = tuple(replace(s, activation=Activation("commands", min_period=0.01, first_timeout=0.5))
                       if s.name == "idle" else s for s in fsm.states)
        inputs = (replace(sub.inputs[0], receive="queue", queue_size=4),) + sub.inputs[1:]
        group = BufferGroup("commands", f"{sub.path}.commands", ("manipulatorCommand/ib",), (), sub.location)
        return replace(sub, fsm=replace(fsm, states=states), inputs=inputs, buffer_groups=(group,))

    changed = _with_subsystem(model, "manip/a.cs", activate)
    assert to_text(diff_models(model, changed)) == """\
changed  input buffer manip/a.cs.manipulatorCommand/ib
           receive: latest → queue
           queue size: 0 → 4
changed  state manip/a.cs.fsm.idle
           activation.group: (none) → commands
           activation.minimum period: (none) → 0.01
           activation.first timeout: (none) → 0.5
added    buffer group manip/a.cs.commands
           obligatory: manipulatorCommand/ib
"""
    assert diff_models(changed, changed) == []


def test_a_change_of_a_replicated_block_is_one_change_with_its_instance_count(tmp_path: Path) -> None:
    assert diff_text(tmp_path, "renamed_replicated_pf") == """\
changed  basic behaviour manip/a.motorControllerK/ve.regulate/bb (×6)
           stages: regulateMotor/pf → regulate/pf
renamed  pf manip/a.motorControllerK/ve.regulateMotor/pf → manip/a.motorControllerK/ve.regulate/pf (×6)
"""

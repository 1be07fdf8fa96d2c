"""The forms of the SysML v2 subset that the sample and the user model do not use
(``tests/fixtures/sysml2/forms.sysml``) lift as docs/sysml-v2.md says, and convert back."""

from __future__ import annotations

from pathlib import Path

from earl_m2t.api import check, load
from earl_m2t.export import model_to_dict

FORMS = Path(__file__).resolve().parent / "fixtures" / "sysml2" / "forms.sysml"


def test_the_other_forms_of_the_subset_lift_as_documented() -> None:
    model = load(FORMS).model
    (agent,) = model.agents
    assert agent.recognised_by == "generalisation"  # LevelAgent :> SensingAgent :> Agent
    assert [(s.name, s.kind, s.recognised_by) for s in agent.subsystems] == [
        ("cs", "cs", "stereotype"), ("gauge/vr", "vr", "stereotype"), ("probe/rr", "rr", "stereotype")]
    cs = agent.subsystems[0]
    assert [(b.name, b.datatype, b.recognised_by) for b in cs.inputs] == [("level/ib", "Reading", "stereotype")]
    assert [(m.name, m.datatype, m.recognised_by) for m in cs.memory] == [("mode", "Mode", "stereotype")]
    assert model.datatypes["Level"].kind == "primitive" and model.datatypes["Mode"].literals == ("low", "high")
    assert [(f.name, f.type, f.lower, f.upper) for f in model.datatypes["Reading"].fields] == [
        ("values", "Level", 0, 4)]
    assert [(p.name, p.language, p.fun.text if p.fun else None) for p in cs.predicates] == [
        ("high/pp", "EARL", "level/ib.msg.values[0] >= 3.5"), ("low/pp", "EARL", "¬newData(level/ib.msg.values)")]
    assert [(e.name, e.predicates) for e in cs.exclusions] == [("", ("high/pp", "low/pp"))]
    decide = cs.function("decide/pf")
    assert decide is not None and decide.body == "if (x) {\n    y();\n}"
    assert [(a.name, a.mode) for a in decide.accesses] == [("level/ib", "read"), ("mode", "readwrite")]
    assert cs.fsm is not None
    assert [(s.name, s.behaviours) for s in cs.fsm.states] == [("filling", ("watch/bb",)), ("draining", ("watch/bb",))]
    assert [(t.name, t.condition.text if t.condition else None) for t in cs.fsm.transitions] == [
        ("filling,draining/t", "high/pp.fun ∧ ¬low/pp.fun"), ("draining,filling/t", "low/pp.fun")]
    (watch,) = cs.behaviours
    assert watch.stages == (("decide/pf",),) and watch.tc is not None and watch.tc.text == "high/pp.fun ∨ low/pp.fun"
    gauge, probe = agent.subsystems[1], agent.subsystems[2]
    assert [(b.name, b.datatype, b.recognised_by) for b in gauge.inputs] == [("raw/ib", "Reading", "suffix")]
    assert probe.fsm is not None and probe.fsm.initial == "run"
    assert gauge.fsm is not None and gauge.fsm.initial == "run"
    assert [b.stages for b in probe.behaviours] == [(("sample/pf",),)]
    assert [(link.source, link.target) for link in agent.links] == [
        ("level/a.probe/rr.raw/ob", "level/a.gauge/vr.raw/ib"), ("level/a.gauge/vr.level/ob", "level/a.cs.level/ib")]
    # the comment on the probe's link suppresses its C008; the other link has no name either
    lines = FORMS.read_text(encoding="utf-8").splitlines()

    def line_of(start: str) -> int:
        return next(n for n, text in enumerate(lines, 1) if text.strip().startswith(start))

    assert sorted((d.code, d.location.line) for d in check(FORMS)) == [
        ("B007", line_of("state filling")), ("B007", line_of("state draining")), ("C008", line_of("flow from"))]


def without_route(value: object) -> object:
    if isinstance(value, dict):
        return {k: without_route(v) for k, v in value.items() if k != "recognised_by"}
    if isinstance(value, list):
        return [without_route(v) for v in value]
    return value


def test_converting_the_other_forms_reads_back_as_the_same_model_but_for_the_route(tmp_path: Path) -> None:
    """`convert` writes every EARL block as specialising its EARL definition directly: the
    agent recognised through SensingAgent comes back recognised by its EARL definition."""
    from test_sample_dialects_equal import without_location

    from earl_m2t.convert import to_sysml

    target = tmp_path / "forms.sysml"
    text = to_sysml(load(FORMS).model)
    target.write_text(text, encoding="utf-8")
    before = without_location(model_to_dict(load(FORMS).model))
    after = without_location(model_to_dict(load(target).model))
    assert before["systems"][0]["agents"][0]["recognised_by"] == "generalisation"
    assert after["systems"][0]["agents"][0]["recognised_by"] == "stereotype"
    assert without_route(after) == without_route(before)
    assert "language \"C++\"\n" in text and "then action 'filter' : 'filter/pf';" in text


def test_the_forms_earlier_versions_wrote_still_read_as_the_same_model(tmp_path: Path) -> None:
    """Metadata typed by the concepts themselves, predicates navigated (`'x/pp'.fun`), `do`
    naming a shared behaviour and an item as a buffer are not valid SysML v2 (a SysML v2 tool
    rejects them), but earl-m2t reads them as it did, as the same model as their valid forms."""
    from test_sample_dialects_equal import without_location

    text = FORMS.read_text(encoding="utf-8")
    earlier = text
    for valid, old in [("#Memory attribute", "#InternalMemory attribute"), ("@Exclusive about", "@Exclusion about"),
                       ("'high/pp'()", "'high/pp'.fun"), ("'low/pp'()", "'low/pp'.fun"),
                       ("do action watching : 'watch/bb';", "do 'watch/bb';"),
                       ("in 'raw/ib' : Reading;", "in item 'raw/ib' : Reading;"),
                       ("Probe::'sample/pf'", "'sample/pf'")]:
        assert valid in earlier, valid
        earlier = earlier.replace(valid, old)
    path = tmp_path / "forms.sysml"
    path.write_text(earlier, encoding="utf-8")
    assert without_location(model_to_dict(load(path).model)) == without_location(model_to_dict(load(FORMS).model))

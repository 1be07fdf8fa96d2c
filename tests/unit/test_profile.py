"""The EARL profile (profiles/earl.sysml) and its loader."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t import resources
from earl_m2t.profile import load_profile
from earl_m2t.profile_types import Concept, Feature, Profile, ProfileError
from earl_m2t.sysml2 import Sysml2SyntaxError, parse_text

# Concept, abbreviation, UML metaclass: earl-metamodel.md §1 and the stereotype mapping.
EXPECTED = [
    ("System", None, "Class"),
    ("Robot", "r", "Class"),
    ("Agent", "a", "Class"),
    ("Subsystem", None, "Class"),
    ("ControlSubsystem", "cs", "Class"),
    ("VirtualEffector", "ve", "Class"),
    ("RealEffector", "re", "Class"),
    ("VirtualReceptor", "vr", "Class"),
    ("RealReceptor", "rr", "Class"),
    ("InputBuffer", "ib", "Port"),
    ("OutputBuffer", "ob", "Port"),
    ("InternalMemory", "m", "Property"),
    ("InterSubsystemLink", None, "Connector"),
    ("InterAgentLink", "aa", "Connector"),
    ("FSM", "fsm", "StateMachine"),
    ("FsmState", "s", "State"),
    ("FsmTransition", "t", "Transition"),
    ("BasicBehaviour", "bb", "Activity"),
    ("TransitionFunction", "tf", "Activity"),
    ("PartialTransitionFunction", "pf", "Behavior"),
    ("Predicate", None, "Constraint"),
    ("PrimitivePredicate", "pp", "Behavior"),
    ("Exclusion", None, "Constraint"),
]


@pytest.fixture(scope="module")
def profile() -> Profile:
    return load_profile()


def copy_profile(tmp_path: Path, edit) -> Path:
    text = resources.profile_path().read_text(encoding="utf-8")
    target = tmp_path / "earl.sysml"
    target.write_text(edit(text), encoding="utf-8")
    return target


# ---------------------------------------------------------------------------- the profile


def test_the_profile_parses_with_the_sysml2_grammar() -> None:
    root = parse_text(resources.profile_path().read_text(encoding="utf-8"), "earl.sysml")
    assert [type(m).__name__ for m in root.members] == ["Package"]


def test_the_default_profile_is_loaded_once_and_cached(profile: Profile) -> None:
    assert load_profile() is profile


@pytest.mark.parametrize(("name", "abbreviation", "metaclass"), EXPECTED)
def test_every_concept_of_the_metamodel_is_present_with_its_abbreviation_and_metaclass(
    profile: Profile, name: str, abbreviation: str | None, metaclass: str
) -> None:
    concept = profile.concepts[name]
    assert concept.abbreviation == abbreviation
    assert concept.metaclass == metaclass


def test_the_abbreviations_of_the_metamodel_all_name_a_concept(profile: Profile) -> None:
    abbreviations = ["cs", "ve", "re", "vr", "rr", "ib", "ob", "m", "bb", "pf", "pp", "t", "a", "r", "aa", "fsm", "s",
                     "tf"]
    found = {abbr: profile.by_abbreviation(abbr) for abbr in abbreviations}
    assert all(isinstance(concept, Concept) for concept in found.values()), found
    assert found["t"].name == "FsmTransition"
    assert found["aa"].name == "InterAgentLink"
    assert profile.by_abbreviation("xyz") is None


def test_concepts_keep_the_order_of_the_profile(profile: Profile) -> None:
    names = list(profile.concepts)
    expected = [name for name, _, _ in EXPECTED]
    assert [n for n in names if n in expected] == expected


def test_every_concept_has_a_doc_and_a_metaclass(profile: Profile) -> None:
    for concept in profile.concepts.values():
        assert concept.doc, concept.name
        assert "Paper" in concept.doc or "earl-m2t" in concept.doc, concept.name
        assert concept.metaclass, concept.name


def test_docs_are_single_lines_without_comment_markers(profile: Profile) -> None:
    doc = profile.concepts["ControlSubsystem"].doc
    assert doc.startswith("Control Subsystem: coordinates")
    assert "/*" not in doc and "*/" not in doc and "\n" not in doc


# ---------------------------------------------------------------------------- features


def multiplicities(concept: Concept) -> dict[str, tuple[int, int | None]]:
    return {f.name: (f.lower, f.upper) for f in concept.features}


def test_agent_features_carry_the_metamodel_multiplicities(profile: Profile) -> None:
    agent = multiplicities(profile.concepts["Agent"])
    assert agent["cs"] == (1, 1)
    for name in ("ve", "re", "vr", "rr"):
        assert agent[name] == (0, None), name
    features = {f.name: f for f in profile.concepts["Agent"].features}
    assert features["cs"].type == "ControlSubsystem"
    assert features["ve"].type == "VirtualEffector"
    assert features["cs"].kind == "part"


def test_system_and_robot_features_carry_the_metamodel_multiplicities(profile: Profile) -> None:
    system = {f.name: f for f in profile.concepts["System"].features}
    assert (system["r"].type, system["r"].lower, system["r"].upper) == ("Robot", 1, None)
    assert (system["a"].type, system["a"].lower, system["a"].upper) == ("Agent", 0, None)
    assert system["aa"].type == "InterAgentLink"
    robot = {f.name: f for f in profile.concepts["Robot"].features}
    assert (robot["a"].lower, robot["a"].upper) == (1, None)
    assert robot["aa"].kind == "ref"


def test_subsystem_is_abstract_and_owns_buffers_memory_fsm_and_behaviours(
    profile: Profile,
) -> None:
    subsystem = profile.concepts["Subsystem"]
    assert subsystem.abstract
    found = multiplicities(subsystem)
    assert found["fsm"] == (1, 1)
    assert found["bb"] == (1, None)
    for name in ("ib", "ob", "m", "pf", "pp"):
        assert found[name] == (0, None), name
    assert subsystem.feature("ib").kind == "port"


def test_basic_behaviour_has_exactly_one_tf_tc_and_ec(profile: Profile) -> None:
    found = multiplicities(profile.concepts["BasicBehaviour"])
    assert found["tf"] == found["tc"] == found["ec"] == (1, 1)


def test_fsm_transition_has_a_priority_tag_with_default_zero(profile: Profile) -> None:
    priority = profile.concepts["FsmTransition"].feature("priority")
    assert priority == Feature(
        name="priority", type="Integer", lower=1, upper=1, kind="attribute", default=0, tag=True
    )


def test_agent_has_optional_declared_type_reactivation_and_host_tags(profile: Profile) -> None:
    declared, reactivation, host = profile.tags("Agent")
    assert (declared.name, declared.type, declared.lower, declared.upper) == ("declaredType", "AgentType", 0, 1)
    assert (reactivation.name, reactivation.type, reactivation.default) == ("reactivation", "Reactivation", "restart")
    assert profile.enums["Reactivation"] == ("restart", "resume")
    assert (host.name, host.type, host.lower, host.upper, host.default) == ("host", "String", 0, 1, None)


def test_the_tags_are_those_of_the_catalogue(profile: Profile) -> None:
    tagged = {(c.name, f.name) for c in profile.concepts.values() for f in c.features if f.tag}
    assert tagged == {("Agent", "declaredType"), ("FsmTransition", "priority"),
                      ("InputBuffer", "receive"), ("InputBuffer", "queueSize"),
                      ("InputBuffer", "reliability"), ("OutputBuffer", "reliability"),
                      ("FsmState", "bufferGroup"), ("FsmState", "minPeriod"), ("FsmState", "firstTimeout"),
                      ("FsmState", "nextTimeout"), ("BufferGroup", "obligatory"), ("BufferGroup", "optional"),
                      ("Agent", "reactivation"), ("Agent", "host"), ("FsmState", "configuration"),
                      ("FsmState", "quiescent"),
                      ("Configuration", "agents"), ("Configuration", "links"), ("Configuration", "switchTimeout"),
                      # what import fabric carries of FABRIC and the orocos target writes back
                      ("FsmState", "behaviours"), ("FsmState", "exclusiveGuards"), ("FsmState", "firstTimeoutSim"),
                      ("FsmState", "minPeriodSim"), ("FsmState", "usedTime"), ("InputBuffer", "channel"),
                      ("InputBuffer", "converter"), ("InputBuffer", "side"), ("OutputBuffer", "channel"),
                      ("OutputBuffer", "converter"), ("OutputBuffer", "side"), ("Subsystem", "triggerGazebo"),
                      ("Subsystem", "useRosSimClock"), ("Subsystem", "useSimClock")}


def test_receive_mode_defaults_to_the_latest_value(profile: Profile) -> None:
    receive = next(f for f in profile.concepts["InputBuffer"].features if f.name == "receive")
    assert (receive.type, receive.default) == ("ReceiveMode", "latest")
    assert profile.enums["ReceiveMode"] == ("latest", "queue")


def test_both_buffers_are_reliable_unless_tagged_best_effort(profile: Profile) -> None:
    for concept in ("InputBuffer", "OutputBuffer"):
        reliability = next(f for f in profile.concepts[concept].features if f.name == "reliability")
        assert (reliability.type, reliability.default) == ("Reliability", "reliable"), concept
    assert profile.enums["Reliability"] == ("reliable", "best_effort")


def test_agent_type_has_the_eight_literals(profile: Profile) -> None:
    assert profile.enums["AgentType"] == ("C", "CT", "CE", "CR", "CET", "CRT", "CER", "CERT")


def test_links_go_from_an_output_buffer_to_an_input_buffer(profile: Profile) -> None:
    for name in ("InterSubsystemLink", "InterAgentLink"):
        ends = {f.name: f for f in profile.all_features(name) if f.kind == "end"}
        assert ends["source"].type == "OutputBuffer"
        assert ends["destination"].type == "InputBuffer"


def test_exclusion_constrains_at_least_two_primitive_predicates(profile: Profile) -> None:
    exclusion = profile.concepts["Exclusion"]
    assert exclusion.metaclass == "Constraint"
    assert "mutually exclusive" in exclusion.doc
    pp = exclusion.feature("pp")
    assert (pp.type, pp.lower, pp.upper) == ("PrimitivePredicate", 2, None)
    assert profile.concepts["Subsystem"].feature("exclusion").type == "Exclusion"


# ---------------------------------------------------------------------------- specialisation


def test_control_subsystem_is_a_subsystem(profile: Profile) -> None:
    assert profile.is_a("ControlSubsystem", "Subsystem")
    assert profile.concepts["ControlSubsystem"].supertypes == ("Subsystem",)


def test_is_a_is_reflexive_and_false_for_unrelated_or_unknown_concepts(profile: Profile) -> None:
    assert profile.is_a("Agent", "Agent")
    assert not profile.is_a("Agent", "Subsystem")
    assert not profile.is_a("Subsystem", "ControlSubsystem")
    assert not profile.is_a("NoSuchConcept", "Subsystem")


def test_ancestors_are_transitive_and_exclude_the_concept(profile: Profile) -> None:
    assert profile.ancestors("InterAgentLink") == ("Link",)
    assert profile.ancestors("Agent") == ()
    with pytest.raises(KeyError):
        profile.ancestors("NoSuchConcept")


def test_the_concrete_kinds_of_subsystem_are_the_five_subsystems(profile: Profile) -> None:
    kinds = [c.abbreviation for c in profile.concrete_kinds("Subsystem")]
    assert kinds == ["cs", "ve", "re", "vr", "rr"]
    assert [c.name for c in profile.concrete_kinds("Agent")] == ["Agent"]


def test_subsystem_kinds_narrow_their_buffers_as_in_figure_4b(profile: Profile) -> None:
    def buffers(name: str) -> tuple[tuple[int, int | None], tuple[int, int | None]]:
        found = {f.name: (f.lower, f.upper) for f in profile.all_features(name)}
        return found["ib"], found["ob"]

    many, some = (0, None), (1, None)
    assert buffers("ControlSubsystem") == (many, many)
    assert buffers("VirtualEffector") == (some, some)
    assert buffers("VirtualReceptor") == (some, some)
    assert buffers("RealEffector") == (some, many)
    assert buffers("RealReceptor") == (many, some)


def test_a_redefinition_keeps_the_type_of_the_feature_it_redefines(profile: Profile) -> None:
    ib = profile.concepts["RealEffector"].feature("ib")
    assert (ib.type, ib.kind, ib.redefines) == ("InputBuffer", "port", "ib")
    names = [f.name for f in profile.all_features("RealEffector")]
    assert names.count("ib") == 1 and "fsm" in names


# ---------------------------------------------------------------------------- errors


def test_a_syntax_error_in_a_copied_profile_raises_profile_error_with_line_and_column(
    tmp_path: Path,
) -> None:
    path = copy_profile(
        tmp_path,
        lambda t: t.replace("part cs : ControlSubsystem[1];", "part cs : ControlSubsystem[1]"),
    )
    line = next(
        n
        for n, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if "part ve : VirtualEffector" in text
    )
    with pytest.raises(ProfileError) as caught:
        load_profile(path)
    error = caught.value
    assert (error.line, error.column) == (line, 13)
    assert str(error).startswith(f"{path}:{line}:13: syntax error at 'part'")
    assert "';'" in error.message
    assert caught.value.__cause__ is None and caught.value.__suppress_context__


def test_a_copied_profile_without_errors_loads_like_the_default(tmp_path: Path) -> None:
    copied = load_profile(copy_profile(tmp_path, lambda t: t))
    assert copied.concepts == load_profile().concepts


def test_an_unknown_supertype_is_a_profile_error(tmp_path: Path) -> None:
    path = copy_profile(
        tmp_path,
        lambda t: t.replace("ControlSubsystem :> Subsystem", "ControlSubsystem :> Subsistem"),
    )
    with pytest.raises(ProfileError, match="specialises 'Subsistem'"):
        load_profile(path)


def test_an_unknown_feature_type_is_a_profile_error(tmp_path: Path) -> None:
    path = copy_profile(tmp_path, lambda t: t.replace("part fsm : FSM[1];", "part fsm : Fsm[1];"))
    with pytest.raises(ProfileError, match="unknown type 'Fsm'"):
        load_profile(path)


def test_a_missing_file_is_a_profile_error(tmp_path: Path) -> None:
    with pytest.raises(ProfileError, match="cannot read"):
        load_profile(tmp_path / "missing.sysml")


# ---------------------------------------------------------------------------- the grammar


def test_the_grammar_reads_quoted_names_notes_imports_and_values() -> None:
    root = parse_text(
        "// a note\n"
        "package 'My Model' {\n"
        "    //* a block note */\n"
        "    private import ScalarValues::*;\n"
        "    /* a comment element */\n"
        "    part def <x> 'X y' :> A::B { attribute n : Real = -1.5; ref r : T[*] ordered; }\n"
        "}\n"
    )
    (package,) = root.members
    assert package.ident.name == "'My Model'"


def test_the_grammar_rejects_a_regular_comment_inside_a_declaration() -> None:
    with pytest.raises(Sysml2SyntaxError):
        parse_text("part def X { part /* c */ p : T; }")

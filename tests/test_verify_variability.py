"""verify on a variable structure, with the real SPIN: the hand-over fixture (a task switching
its commands between two manipulators) proves the switch checks V006-V009 and a property over
the new atoms; a manipulator that can get stuck in a non-quiescent state with commands queued
loses them (V006), one whose quiescent state is out of reach of a leaving run only stops by the
timeout (V007); the counterexamples name the switch, the stuck state and the values cleared.
The harmoniser sample proves V006-V009 and its property in each of its four files."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_sample_dialects_equal import SAMPLE_FILES

from earl_m2t.api import load
from earl_m2t.cli.app import main
from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.location import Location
from earl_m2t.verify import spin
from earl_m2t.verify.ltl import AgentAtom, ConfigAtom, LtlError, StateAtom, SwitchingAtom, tokens
from earl_m2t.verify.promela import translate
from earl_m2t.verify.run import Finding, TraceStep
from earl_m2t.verify.sequence import counterexample_dot
from earl_m2t.verify.switching import DROP_CLAIM

ROOT = Path(__file__).resolve().parents[1]
FIXTURE = ROOT / "tests" / "fixtures" / "variability" / "handover.sysml"
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"
EXCLUSIVE = "[] (config@useB -> !manipA/a@active)"
PROVEN = ("no switch loses values", "every switch can end without its timeout",
          "exclusivity: agents that share no configuration never run together (manipA/a and manipB/a)",
          "no leaving agent's send is dropped")

# a state that never receives and is not quiescent, entered from moving while commands wait
STUCK = [
    ('            metadata commands : Group { obligatory = "command/ib"; optional = ""; }\n',
     '            metadata commands : Group { obligatory = "command/ib"; optional = ""; }\n'
     '            metadata nothing : Group { obligatory = ""; optional = ""; }\n'
     "            attribute 'faults/m' : Integer;\n"
     "            calc def 'fault/pp' { return : Boolean; 'faults/mi'.data > 0 }\n"),
    ("                transition 'idle,moving/t' first idle then moving {\n",
     "                state stuck {\n"
     '                    @Activation { bufferGroup = "nothing"; }\n'
     "                    do action 'stuck/bb' { first start; then done; constraint tc { false } "
     "constraint ec { false } }\n"
     "                }\n"
     "                transition 'moving,stuck/t' first moving then stuck { language \"EARL\" /* fault/pp */ }\n"
     "                transition 'idle,moving/t' first idle then moving {\n"),
]
# moving quiescent instead of idle: a manipulator leaving in idle waits there for ever
QUIET_MOVING = [
    ("                    @Quiescent;\n", ""),
    ("                state moving {\n", "                state moving {\n                    @Quiescent;\n"),
]


def _variant(tmp_path: Path, replacements: list[tuple[str, str]]) -> Path:
    text = FIXTURE.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / "variant.sysml"
    path.write_text(text, encoding="utf-8")
    return path


def _property(text: str) -> LtlProperty:
    return LtlProperty("p", text, Location("--ltl", 1, 1))


def test_the_fixture_proves_the_switch_checks_and_its_exclusivity(capsys: pytest.CaptureFixture[str]) -> None:
    ends = "[] (switching -> <> !switching)"
    code = main(["verify", str(FIXTURE), "--format", "json", "--ltl", EXCLUSIVE, "--ltl", ends,
                 "--ltl", "[] !manipB/a@active"])
    result = json.loads(capsys.readouterr().out)

    assert code == 1 and result["not_proven"] == []
    assert all(any(line.startswith(text) for line in result["proven"]) for text in PROVEN), result["proven"]
    assert f"{EXCLUSIVE} holds" in result["proven"] and f"{ends} holds" in result["proven"]
    (finding,) = result["findings"]  # manipB/a runs once a switch to useB is done
    assert finding["code"] == "V005"
    whys = [step["by"] for step in finding["trace"]]
    assert any("the switch useA → useB begins, leaving: manipA/a" in why for why in whys), whys
    assert any(why.startswith("the drain: quiescent in manipA/a.cs@idle") for why in whys), whys
    assert whys[-1] == "the switch useA → useB is done: manipB/a resumes"


def test_a_manipulator_stuck_with_commands_queued_loses_them(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    stuck = _variant(tmp_path, STUCK)
    assert main(["verify", str(stuck)]) == 2  # the rules see it: nothing verified without --force
    refused = capsys.readouterr()
    assert refused.out == "" and "nothing verified (--force to verify anyway)" in refused.err
    code = main(["verify", str(stuck), "--force"])
    out = capsys.readouterr().out

    assert code == 1
    (finding,) = [line for line in out.splitlines() if " V006 error: " in line]
    assert "a switch can lose values on task/a,manip" in finding
    assert "ends by its timeout with" in finding and "@stuck, not quiescent" in finding
    trace = out.split(" counterexample:\n", 1)[1].split("\nproven:", 1)[0].splitlines()
    assert trace[-3].endswith("task/a.cs: switching → timed out by the switch timeout: nothing else can move")
    assert "running → stopped by the switch timeout: stuck in manip" in trace[-2] and trace[-2].endswith("@stuck")
    assert trace[-1].endswith("queued → cleared by the switch timeout: undelivered")
    assert any("→ stuck by moving,stuck/t" in line for line in trace)
    assert " V007 " not in out  # the loss is a switch its timeout ended: reported once
    assert "proven: exclusivity" in out


def test_a_leaving_manipulator_that_cannot_reach_a_quiescent_state_stops_by_the_timeout(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["verify", str(_variant(tmp_path, QUIET_MOVING)), "--format", "json", "--force"])
    result = json.loads(capsys.readouterr().out)

    assert code == 1
    (finding,) = [f for f in result["findings"] if f["code"] == "V007"]
    assert finding["element"] == "manipA/a" or finding["element"] == "manipB/a"
    assert "can only end by its timeout" in finding["message"] and "@idle, not quiescent" in finding["message"]
    assert any(line.startswith("no switch loses values") for line in result["proven"])


def test_the_atoms_of_a_variable_structure() -> None:
    model = load(FIXTURE).model
    written = tokens(_property("[] (config@useB && switching -> manipA/a@active || manipA/a.cs@idle)"), model)
    assert ConfigAtom("useB") in written and SwitchingAtom() in written
    assert AgentAtom("manipA/a") in written and StateAtom("manipA/a.cs", "idle") in written
    spec = translate(model, (_property("[] (config@useB -> !manipA/a@active)"),))
    assert spec.formulas["p"] == "[] ( (cfg == 1) -> ! active0 )"
    with pytest.raises(LtlError, match="no configuration useC"):
        tokens(_property("[] config@useC"), model)
    with pytest.raises(LtlError, match="no agent manipC/a"):
        tokens(_property("[] manipC/a@active"), model)


def test_a_fixed_structure_reads_the_atoms_as_constants() -> None:
    model = load(SAMPLE).model
    spec = translate(model, (_property("[] (!switching && manip/a@active)"),))
    assert spec.formulas["p"] == "[] ( ! false && true )"
    assert "switching" not in spec.text.split("ltl p")[0]


def test_the_promela_of_the_fixture_encodes_the_switch() -> None:
    text = translate(load(FIXTURE).model).text
    assert "byte cfg = 0; /* configuration: 0=useA 1=useB */" in text
    assert "bool active0 = true; /* manipA/a is running */" in text
    assert "bool active1 = false; /* manipB/a is running */" in text
    # the task's command reaches manipB/a only while useB holds and no switch closes it
    assert "if :: (cfg == 1) && (!switching || nxt == 1) && q1 < 32 -> q1++ :: else -> skip fi" in text
    # leaving manipA/a stops in its quiescent idle with its commands received
    assert "leaving0 && active0 && (st0 == 0) && q0 == 0 -> active0 = false" in text
    assert "timeout && switching" in text


# the task waits for the manipulators' status in withB: status/ib, which both manipulators'
# variable links deliver to, is counted per link; the manipulators restart when they join
PER_LINK = [
    ("            port 'status/ib' : InputBuffer { attribute :>> msg : DataTypes::Status; }\n",
     "            port 'status/ib' : InputBuffer {\n"
     "                attribute :>> msg : DataTypes::Status;\n"
     "                @Receive { receive = ReceiveMode::queue; queueSize = 2; }\n"
     "            }\n"
     '            metadata statuses : Group { obligatory = "status/ib"; optional = ""; }\n'),
    ('                    @Reconfigure { configuration = "useB"; }\n',
     '                    @Reconfigure { configuration = "useB"; }\n'
     '                    @Activation { bufferGroup = "statuses"; }\n'),
    ("@AgentReactivation { reactivation = Reactivation::resume; }",
     "@AgentReactivation { reactivation = Reactivation::restart; }"),
]


def test_an_input_of_two_variable_links_counts_per_link(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _variant(tmp_path, PER_LINK)
    text = translate(load(path).model).text
    assert "byte q2 = 0; /* task/a.cs.status/ib by manipA/a,task/a, up to 2 */" in text
    assert "byte q3 = 0; /* task/a.cs.status/ib by manipB/a,task/a, up to 2 */" in text
    # open while useA holds and, during a switch, while useA is next or manipA/a drains towards useB
    lingering = "(cfg == 0) && (!switching || nxt == 0 || leaving0 && active0 && nxt == 1)"
    assert f"if :: {lingering} && (q2 + q3) < 2 -> q2++ :: else -> skip fi" in text
    # the search of V009 tells a send the closed link drops
    dropped = f"switching && leaving0 && active0 && (cfg == 0) && !({lingering})"
    mark = 'printf("EARLSWITCH dropped q2 %d\\n", nxt); dropped = true'
    assert f"if :: {lingering} && (q2 + q3) < 2 -> q2++ :: {dropped} -> {mark} :: else -> skip fi" in translate(
        load(path).model, (), DROP_CLAIM).text
    assert "if :: q2 > 0 -> q2-- :: q3 > 0 -> q3-- :: else -> skip fi" in text
    assert "st0 = (active0 -> st0 : 0); q0 = (active0 -> q0 : 0); active0 = true" in text  # restarts

    code = main(["verify", str(path), "--format", "json", "--force"])  # the rules see the wait too
    result = json.loads(capsys.readouterr().out)
    # withB waits for a status: the one manipA/a sends while it drains the command that began the
    # switch lingers to the task (closed at the decision, it deadlocked: test_verify_lingering.py)
    assert code == 0 and result["findings"] == [], result["findings"]
    assert all(any(line.startswith(text) for line in result["proven"]) for text in PROVEN), result["proven"]


def test_a_counterexample_diagram_has_lifelines_for_the_agents_and_links_of_a_switch() -> None:
    model = load(FIXTURE).model
    trace = (TraceStep(1, "task/a.cs", "switching", "timed out", "the switch timeout: nothing else can move", ()),
             TraceStep(2, "manipA/a", "running", "stopped", "the switch timeout: stuck in manipA/a.cs@moving", ()),
             TraceStep(3, "task/a,manipA/a", "1 queued", "cleared", "the switch timeout: undelivered", ()))
    finding = Finding("V006", "a switch can lose values", "task/a,manipA/a", Location("x.sysml", 1), trace)
    dot = counterexample_dot(model, finding).decode()
    assert '<font point-size="8" color="#5d6d7e"></font>' not in dot  # Graphviz rejects an empty line
    assert "<b>manipA/a</b><br/>" in dot and ">agent</font>" in dot and ">link</font>" in dot


def test_a_latest_input_of_two_variable_links_keeps_the_newest_value(tmp_path: Path) -> None:
    latest = [(old, new.replace("                @Receive { receive = ReceiveMode::queue; queueSize = 2; }\n", ""))
              for old, new in PER_LINK]
    spec = translate(load(_variant(tmp_path, latest)).model)
    assert "if :: (cfg == 0) && (!switching || nxt == 0 || leaving0 && active0 && nxt == 1) -> q2 = 1; q3 = 0 " \
           ":: else -> skip fi" in spec.text
    assert "q2 = 0; q3 = 0" in spec.text  # an iteration receives the one value
    spin.build(tmp_path, spec.text, "pan", ("-DSAFETY",), 120)  # SPIN and the compiler accept it


def test_leaving_is_false_in_an_agent_that_is_always_present(tmp_path: Path) -> None:
    path = _variant(tmp_path, [('constraint tc { language "EARL" /* handOver/pp */ }',  # withA's
                                'constraint tc { language "EARL" /* handOver/pp and leaving() */ }')])
    spec = translate(load(path).model)
    task = spec.text.split("/* task/a.cs */", 1)[1].split("active proctype", 1)[0]
    assert "&& leaving" not in task and "&& !leaving" not in task  # its outcomes take leaving() false
    assert "/* withA: goes on */" in task and "/* withA: withA,withB/t" not in task  # so withA never ends
    assert "/* withB: withB,withA/t */" in task


HARMONISER_PROVEN = (
    "no switch loses values", "every switch can end without its timeout",
    "exclusivity: agents that share no configuration never run together (guide/a and fallHelp/a)",
    "no leaving agent's send is dropped", "[] (config@fallResponse -> !guide/a@active) holds",
)


@pytest.mark.parametrize("dialect", ["papyrus", "cameo", "ea", "sysml"])
def test_the_harmoniser_sample_proves_its_switches_lossless_and_its_property(
    dialect: str, capsys: pytest.CaptureFixture[str],
) -> None:
    """samples/harmoniser in each dialect: V006-V009, the sample's «LtlProperty», and that
    guide/a is only ever stopped (or not yet started) in its quiescent state waiting, where a
    resume finds it."""
    stopped_in_waiting = "[] (!guide/a@active -> guide/a.cs@waiting)"
    path = SAMPLE_FILES["harmoniser"][dialect]
    code = main(["verify", str(path), "--format", "json", "--ltl", stopped_in_waiting])
    result = json.loads(capsys.readouterr().out)

    assert code == 0 and result["findings"] == [] and result["not_proven"] == []
    # tiago/a.cs sends the status every leaving agent must take before it stops
    assert result["processes"] == ["tiago/a.cs", "tha/a.cs", "guide/a.cs", "fallHelp/a.cs"]
    assert all(any(line.startswith(text) for line in result["proven"]) for text in HARMONISER_PROVEN), result
    assert f"{stopped_in_waiting} holds" in result["proven"]


HOSTILE = [  # a configuration name a printf string cannot hold as it is: quotes and a conversion
    ("metadata useB : Structure", "metadata 'use \\\"B\\\" 100%d' : Structure"),
    ('configuration = "useB"', 'configuration = "use \\"B\\" 100%d"'),
]


def test_names_never_reach_the_promela_printf_strings(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The switch marks carry numbers, and the counterexample gets the names back from the model."""
    hostile = _variant(tmp_path, HOSTILE)
    assert main(["check", str(hostile)]) == 0
    capsys.readouterr()
    code = main(["verify", str(hostile), "--format", "json", "--ltl", "[] !manipB/a@active"])
    result = json.loads(capsys.readouterr().out)
    assert code == 1, result
    (finding,) = result["findings"]
    whys = [step["by"] for step in finding["trace"]]
    assert whys[-1] == 'the switch useA → use "B" 100%d is done: manipB/a resumes', whys


# the manipulators run on their period: idle (quiescent) holds without reading command/ib and is
# left for moving, which reads it, unless leaving(); a switch that finds a command queued while a
# manipulator is in idle waits for it in vain
PERIODIC_IDLE = [
    ('            metadata commands : Group { obligatory = "command/ib"; optional = ""; }\n',
     "            action def 'hold/pf' { out 'status/ob'; language \"C++\" /* // Holds. */ }\n"),
    ('''                    @Activation { bufferGroup = "commands"; nextTimeout = 0.01; }
                    do action 'idle/bb' {
                        first start;
                        then action follow : 'follow/pf';
                        then done;
                        constraint tc { language "EARL" /* newCommand/pp and not leaving() */ }''',
     '''                    do action 'idle/bb' {
                        first start;
                        then action hold : 'hold/pf';
                        then done;
                        constraint tc { language "EARL" /* not leaving() */ }'''),
    ('''                    @Activation { bufferGroup = "commands"; nextTimeout = 0.01; }
                    do action 'moving/bb' {''', "                    do action 'moving/bb' {"),
    ('constraint tc { language "EARL" /* leaving() or not newCommand/pp */ }',
     'constraint tc { language "EARL" /* leaving() */ }'),
    ('first idle then moving {\n                    language "EARL" /* newCommand/pp and not leaving() */',
     'first idle then moving {\n                    language "EARL" /* not leaving() */'),
    ('first moving then idle {\n                    language "EARL" /* leaving() or not newCommand/pp */',
     'first moving then idle {\n                    language "EARL" /* leaving() */'),
]


def test_a_queue_a_quiescent_state_never_reads_is_a_switch_that_loses_values(
    tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    """A state receives what its behaviour reads (earl_m2t.analysis.receiving), as the generated
    code does: a quiescent state of a periodic subsystem does not take every input, and a queued
    input of a leaving agent is counted although no state waits for it."""
    path = _variant(tmp_path, PERIODIC_IDLE)
    code = main(["verify", str(path), "--format", "json"])
    result = json.loads(capsys.readouterr().out)
    assert code == 1 and {f["code"] for f in result["findings"]} == {"V006"}, result
    assert any("stuck in manipA/a.cs@idle" in step["by"] for f in result["findings"] for step in f["trace"]), result


def test_the_liveness_of_a_switch_fails_on_free_predicates_as_docs_verify_says(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """docs/verify.md no longer recommends ``[] (switching -> <> !switching)``: without fairness
    it fails on samples/two_arm, the leaving manipA/a cycling on newCommand with its links closed."""
    ends = "[] (switching -> <> !switching)"
    code = main(["verify", str(SAMPLE_FILES["two_arm"]["sysml"]), "--format", "json", "--ltl", ends])
    result = json.loads(capsys.readouterr().out)
    assert code == 1 and [f["code"] for f in result["findings"]] == ["V005"], result
    steps = result["findings"][0]["trace"]
    assert any(s["subsystem"] == "manipA/a.cs" and s["to"] == "moving" and s["values"].get("leaving()") for s in steps)

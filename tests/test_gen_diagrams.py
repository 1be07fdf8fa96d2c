"""The diagrams target: every diagram of the sample is laid out by the real Graphviz dot
without a warning and without overlapping labels, shows what the model says, and comes out
byte-identical on every run; dot's warnings and its absence are clean errors."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from html import escape
from pathlib import Path
from typing import Any

import pytest

from earl_m2t.api import load
from earl_m2t.cli.app import main
from earl_m2t.gen import GenError, render
from earl_m2t.gen.diagrams import diagram_sources, render_diagrams
from earl_m2t.gen.dot import DotError, html_label_text, run_dot

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"

pytestmark = pytest.mark.skipif(shutil.which("dot") is None,
                                reason="Graphviz dot is missing (./dev installs graphviz)")

EXPECTED = {
    "system", "agent-manip-a", "agent-grip-a", "agent-task-a",
    "fsm-manip-a-cs", "tf-manip-a-cs-idle-bb", "tf-manip-a-cs-jointMove-bb", "tf-manip-a-cs-operationalMove-bb",
    "tf-manip-a-cs-emergencyStop-bb", "fsm-manip-a-motorControllerK-ve", "tf-manip-a-motorControllerK-ve-regulate-bb",
    "fsm-manip-a-motorK-re", "tf-manip-a-motorK-re-drive-bb", "fsm-grip-a-cs", "tf-grip-a-cs-operate-bb",
    "fsm-grip-a-fingerController-ve", "tf-grip-a-fingerController-ve-regulate-bb", "fsm-grip-a-fingerMotor-re",
    "tf-grip-a-fingerMotor-re-drive-bb", "fsm-task-a-cs", "tf-task-a-cs-supervise-bb", "tf-task-a-cs-abort-bb",
}


@pytest.fixture(scope="module")
def model() -> Any:
    return load(SAMPLE).model


@pytest.fixture(scope="module")
def sources(model: Any) -> dict[str, bytes]:
    return {diagram.name: source for diagram, source in diagram_sources(model)}


@pytest.fixture(scope="module")
def svgs(model: Any) -> dict[str, str]:
    files = render(model, "diagrams").generated
    return {path.removesuffix(".svg"): content.decode() for path, content in files.items() if path.endswith(".svg")}


def label_boxes(layout: dict[str, Any]) -> list[tuple[int, float, float, float, float, str]]:
    """(owner, x0, y0, x1, y1, text) of every text dot draws, from its -Tjson output."""
    boxes = []
    for owner in [layout] + layout.get("objects", []) + layout.get("edges", []):
        size = 14.0
        for key in ("_ldraw_", "_hldraw_", "_tldraw_"):
            for op in owner.get(key, []):
                if op["op"] == "F":
                    size = float(op["size"])
                elif op["op"] == "T":
                    x, y = op["pt"]
                    width = float(op["width"])
                    left = {"l": x, "c": x - width / 2, "r": x - width}[op["align"]]
                    boxes.append((id(owner), left, y - 0.25 * size, left + width, y + 0.8 * size, op["text"]))
    return boxes


def overlaps(layout: dict[str, Any]) -> list[tuple[str, str]]:
    """Pairs of texts of different nodes, edges or clusters whose boxes intersect."""
    boxes = label_boxes(layout)
    return [(a[5], b[5]) for i, a in enumerate(boxes) for b in boxes[i + 1:]
            if a[0] != b[0] and a[1] < b[3] and b[1] < a[3] and a[2] < b[4] and b[2] < a[4]]


def test_the_sample_has_one_diagram_per_system_agent_fsm_and_behaviour(sources: dict[str, bytes]) -> None:
    assert set(sources) == EXPECTED


def test_dot_lays_out_every_diagram_without_a_warning(sources: dict[str, bytes]) -> None:
    for name, source in sources.items():
        for fmt in ("svg", "png"):
            result = run_dot(source, fmt, name)
            assert result.warnings == (), f"{name}.{fmt}: {result.warnings}"
            assert result.output


def test_no_two_labels_overlap(sources: dict[str, bytes]) -> None:
    for name, source in sources.items():
        layout = json.loads(run_dot_json(source))
        assert overlaps(layout) == [], name


def run_dot_json(source: bytes) -> bytes:
    return subprocess.run(["dot", "-Tjson"], input=source, capture_output=True, check=True, timeout=60).stdout


def test_the_overlap_check_sees_an_overlap() -> None:
    def text(x: float, y: float, what: str) -> dict[str, Any]:
        return {"_ldraw_": [{"op": "F", "size": 10},
                            {"op": "T", "pt": [x, y], "align": "c", "width": 60, "text": what}]}

    assert overlaps({"objects": [text(100, 100, "a"), text(130, 104, "b")]}) == [("a", "b")]
    assert overlaps({"objects": [text(100, 100, "a"), text(200, 100, "b")]}) == []


def test_the_diagrams_show_the_model(svgs: dict[str, str]) -> None:
    system = svgs["system"]
    for text in ("manip/a", "type CET: teleoperated agent", "type CT: purely computational agent",
                 "ManipulatorCommand", "ManipulatorState", "GripperCommand", "GripperStatus", "pickAndPlace/r"):
        assert text in system, text
    assert system.count('class="edge"') == 4
    agent = svgs["agent-manip-a"]
    assert agent.count('class="edge"') == 24  # 6 joints × (cs→ve, ve→cs, ve→re, re→ve)
    for text in ("cs: control subsystem", "ve: virtual effectors", "re: real effectors", "motorController6/ve",
                 "motor6/re", "motorControllerCommand6/ob", "MotorCurrent", "EncoderReading"):
        assert text in agent, text
    fsm = svgs["fsm-manip-a-cs"]
    assert fsm.count('class="edge"') == 9 + 1  # the transitions and the initial arrow
    for text in ("newJointPos/pp ∧ ¬emergencyStop/pp", "¬emergencyStop/pp", "priority 2", "bb: idle/bb"):
        assert text in fsm, text
    tf = svgs["tf-manip-a-cs-jointMove-bb"]
    for text in ("stage 1", "stage 2", "jointMove/pf", "windingCurrentK/m", "motorControllerCommandK/ob"):
        assert text in tf, text
    # reads / writes: jointMove/pf 2 / 2, calculatePosition/pf 1 / 2, outputManipState/pf 4 / 1, outputMotorCon/pf 2 / 1
    assert tf.count('class="edge"') == 4 + 3 + 5 + 3


def test_the_output_is_the_same_on_every_run_and_names_no_graphviz_version(model: Any) -> None:
    first = render(model, "diagrams-png").generated
    second = render(model, "diagrams-png").generated
    assert first == second
    assert {Path(p).suffix for p in first} == {".dot", ".svg", ".png"}
    assert {Path(p).stem for p in first} == EXPECTED
    assert not any(b"graphviz version" in content for path, content in first.items() if path.endswith(".svg"))


def test_gen_writes_the_diagrams(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["gen", str(SAMPLE), "--target", "diagrams", "-o", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [f"{n}.{s}" for n in EXPECTED for s in ("dot", "svg")] + [".earl-trace.json"])  # + the source map
    assert main(["gen", str(SAMPLE), "--target", "diagrams", "-o", str(tmp_path)]) == 0
    assert all(line.startswith("unchanged ") for line in capsys.readouterr().out.splitlines()[len(EXPECTED) * 2 + 1:])


def test_a_template_without_the_generated_marker_is_refused(model: Any, tmp_path: Path) -> None:
    (tmp_path / "tf.dot.j2").write_text("digraph tf { }\n")
    with pytest.raises(GenError, match=r"template tf\.dot\.j2 must start with '// Generated by earl-m2t'"):
        diagram_sources(model, templates=tmp_path)


def test_diagrams_of_elements_no_longer_in_the_model_are_reported_and_kept(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # what an earlier run wrote for a state machine since renamed, and a user's own diagram
    (tmp_path / "fsm-old-cs.dot").write_bytes(b"// Generated by earl-m2t from an EARL model.\ndigraph fsm {}\n")
    (tmp_path / "fsm-old-cs.svg").write_bytes(b"<svg/>")
    (tmp_path / "notes.dot").write_bytes(b"digraph notes {}\n")
    assert main(["gen", str(SAMPLE), "--target", "diagrams", "-o", str(tmp_path)]) == 0
    orphaned = [line for line in capsys.readouterr().out.splitlines() if line.startswith("orphaned ")]
    assert orphaned == [f"orphaned {tmp_path / name} (kept; nothing in the model generates it any more)"
                        for name in ("fsm-old-cs.dot", "fsm-old-cs.svg")]
    assert (tmp_path / "fsm-old-cs.svg").is_file() and (tmp_path / "notes.dot").is_file()
    report = tmp_path / "report"
    (report / "diagrams").mkdir(parents=True)
    shutil.copy(tmp_path / "fsm-old-cs.dot", report / "diagrams" / "fsm-old-cs.dot")
    assert main(["report", str(SAMPLE), "-o", str(report)]) == 0
    assert capsys.readouterr().out.splitlines()[1:] == [
        f"orphaned {report / 'diagrams' / 'fsm-old-cs.dot'} (kept; nothing in the model generates it any more)"]


def test_a_dot_warning_is_an_error_unless_forced(model: Any, tmp_path: Path) -> None:
    assert run_dot(b"digraph g { a [shape=nosuchshape]; }", "svg").warnings
    (tmp_path / "fsm.dot.j2").write_text('// Generated by earl-m2t\n'
                                         'digraph fsm { x [shape=nosuchshape, label="{{ title|h }}"]; }\n')
    with pytest.raises(DotError, match=r"dot warned on fsm-manip-a-cs\.dot: .*nosuchshape"):
        render_diagrams(model, templates=tmp_path)
    forced = render_diagrams(model, templates=tmp_path, strict=False)
    assert any(item.warnings for item in forced)


def test_without_dot_gen_says_so_in_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setenv("PATH", str(tmp_path))
    assert main(["gen", str(SAMPLE), "--target", "diagrams", "-o", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert err == ("earl-m2t: gen: Graphviz 'dot' was not found on PATH; install Graphviz "
                   "(Debian: apt-get install graphviz)\n")
    assert not (tmp_path / "out").exists()
    with pytest.raises(GenError):
        run_dot(b"digraph g {}", "svg")


def test_a_broken_dot_source_is_a_one_line_error() -> None:
    with pytest.raises(DotError, match=r"^dot failed on broken: .*syntax error"):
        run_dot(b"digraph g { a -> }", "svg", "broken")
    assert re.fullmatch(r"unknown diagram format 'pdf' .*", str(pytest.raises(DotError, run_dot, b"", "pdf").value))


def test_a_name_longer_than_dot_reads_is_shortened_in_the_middle_and_laid_out() -> None:
    name = "Arm" + "A" * 30000 + "Robot<&>"
    shown = html_label_text(name, 400)
    assert shown.startswith("ArmAAA") and shown.endswith("Robot&lt;&amp;&gt;") and "…" in shown
    assert len(html_label_text(name, 400).replace("&lt;", "<").replace("&amp;", "&").replace("&gt;", ">")) == 400
    assert html_label_text("a<b", 400) == "a&lt;b"
    with pytest.raises(DotError, match="syntax error"):
        run_dot(f"digraph g {{ a [label=<{'A' * 30000}>]; }}".encode(), "svg", "unshortened")
    assert run_dot(f"digraph g {{ a [label=<{shown}>]; }}".encode(), "svg", "shortened").output



@pytest.mark.parametrize("name", ["", "\n", "\t", "\r\n"], ids=["empty", "newline", "tab", "line-end"])
def test_a_name_of_white_space_alone_is_shown_unnamed_and_laid_out(name: str) -> None:
    with pytest.raises(DotError, match="syntax error"):
        run_dot(f"digraph g {{ a [label=<robot <b>{escape(name)}</b>>]; }}".encode(), "svg", "as it is")
    shown = html_label_text(name, 400)
    assert shown == "(unnamed)"
    assert run_dot(f"digraph g {{ a [label=<robot <b>{shown}</b>>]; }}".encode(), "svg", "unnamed").output

def test_dot_is_bounded_by_its_cpu_time_not_by_the_clock() -> None:
    nodes = [f"n{i}" for i in range(250)]
    heavy = "digraph g {\n" + "".join(f"{a} -> {b};\n" for a in nodes for b in nodes[:60]) + "}\n"
    with pytest.raises(DotError, match=r"^dot used more than 1 s of CPU time on heavy$"):
        run_dot(heavy.encode(), "svg", "heavy", cpu_seconds=1)

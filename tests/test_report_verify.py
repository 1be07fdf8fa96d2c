"""`earl-m2t report --verify`: the verification section and a counterexample as a sequence diagram
rendered by the real dot, from a property written in the model."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from earl_m2t.cli.app import main

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"
ANCHOR = "part def PickAndPlaceSystem :> System {"


def test_report_shows_the_counterexample_as_a_sequence_diagram(tmp_path: Path) -> None:
    model = tmp_path / "model.sysml"
    directive = "earl-m2t: ltl stayJoint: [] (manip/a.cs@jointMove -> [] manip/a.cs@jointMove)"
    model.write_text(SAMPLE.read_text(encoding="utf-8").replace(ANCHOR, f"{ANCHOR}\n    comment /* {directive} */"),
                     encoding="utf-8")
    out = tmp_path / "report"

    assert main(["report", str(model), "-o", str(out), "--verify"]) == 0

    page = (out / "index.html").read_text(encoding="utf-8")
    assert 'id="report-verification"' in page and "V005" in page and "stayJoint" in page
    assert 'src="diagrams/counterexample-1.svg"' in page
    dot = (out / "diagrams" / "counterexample-1.dot").read_text(encoding="utf-8")
    assert "idle → jointMove by idle,jointMove/t" in dot and "newJointPos=true" in dot
    svg = etree.parse(str(out / "diagrams" / "counterexample-1.svg"))
    texts = " ".join(t.text or "" for t in svg.iter("{http://www.w3.org/2000/svg}text"))
    assert "manip/a.cs" in texts and "jointMove" in texts


def test_report_without_verify_has_no_verification_section(tmp_path: Path) -> None:
    out = tmp_path / "report"
    assert main(["report", str(SAMPLE), "-o", str(out)]) == 0
    assert 'id="report-verification"' not in (out / "index.html").read_text(encoding="utf-8")

"""``earl-m2t report`` and ``gen --target markdown``: one self-contained folder, every link to
an element lands on an element of the page, findings link to their elements, the output is
the same on every run, and bad input is a one-line error."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from lxml import html

from earl_m2t.cli.app import main
from earl_m2t.gen.targets.markdown import code_span, escape_markdown

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
PREDICATE_ERRORS = ROOT / "tests" / "fixtures" / "guide" / "predicate-errors.uml"

needs_dot = pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz dot is missing (./dev installs graphviz)")


def report(model: Path, out: Path, *options: str) -> html.HtmlElement:
    assert main(["report", str(model), "-o", str(out), *options]) == 0
    return html.fromstring((out / "index.html").read_bytes())


def internal_links_resolve(page: html.HtmlElement, out: Path) -> None:
    ids = set(page.xpath("//@id"))
    assert len(ids) == len(page.xpath("//@id")), "an id is used twice"
    for ref in page.xpath("//@href | //@src"):
        assert not re.match(r"^[a-z]+:", ref), f"{ref}: the report must not load anything from elsewhere"
        if ref.startswith("#"):
            assert ref[1:] in ids, ref
        else:
            assert (out / ref).is_file(), ref


@needs_dot
def test_the_sample_report_is_one_self_contained_folder(tmp_path: Path) -> None:
    page = report(SAMPLE, tmp_path)
    internal_links_resolve(page, tmp_path)
    assert page.xpath("//script") == [] and page.xpath("//link") == []
    assert len(page.xpath("//figure/a/img")) == 22
    nav = [a.get("href") for a in page.xpath("//nav//a")]
    assert nav[:2] == ["#PickAndPlaceSystem", "#report-findings"]
    assert {"#manip-a", "#manip-a-cs", "#manip-a-motorControllerK-ve", "#manip-a-motorK-re", "#grip-a",
            "#grip-a-cs", "#task-a", "#task-a-cs"} <= set(nav)
    assert "No findings" in page.get_element_by_id("report-findings").text_content()
    instance = page.get_element_by_id("manip-a-motorController3-ve")
    assert instance.getparent().get("id") == "manip-a-motorControllerK-ve"


@needs_dot
def test_findings_link_to_their_elements(tmp_path: Path) -> None:
    page = report(PREDICATE_ERRORS, tmp_path)
    internal_links_resolve(page, tmp_path)
    rows = page.get_element_by_id("report-findings").xpath(".//tr[td]")
    found = {row.findall("td")[0].text_content(): row.xpath(".//a/@href") for row in rows}
    assert found == {"B008": ["#manip-a-cs-fsm-run-halt-t"], "B005": ["#manip-a-cs-halt-bb"], "S006": ["#manip-a"],
                     "C007": ["#manip-a-cs-command-ib"]}
    # the condition that does not parse is shown as written
    cell = page.get_element_by_id("manip-a-cs-fsm-run-halt-t").findall("td")[3].text_content()
    assert "∧" in cell


@needs_dot
def test_the_report_is_the_same_on_every_run_and_png_on_request(tmp_path: Path) -> None:
    report(SAMPLE, tmp_path / "a")
    report(SAMPLE, tmp_path / "b", "--png")
    files_a = {p.relative_to(tmp_path / "a"): p.read_bytes() for p in (tmp_path / "a").rglob("*") if p.is_file()}
    files_b = {p.relative_to(tmp_path / "b"): p.read_bytes() for p in (tmp_path / "b").rglob("*") if p.is_file()}
    pngs = {p for p in files_b if p.suffix == ".png"}
    assert len(pngs) == 22 and all(files_b[p].startswith(b"\x89PNG") for p in pngs)
    assert {p: c for p, c in files_b.items() if p not in pngs} == files_a


@needs_dot
def test_an_unwritable_output_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["report", str(SAMPLE), "-o", str(blocker)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("earl-m2t: report: ") and err.count("\n") == 1


def test_an_unreadable_model_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["report", str(tmp_path / "missing.uml"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("earl-m2t: report: ") and err.count("\n") == 1
    assert not (tmp_path / "out").exists()


def test_the_markdown_target_writes_one_file(tmp_path: Path) -> None:
    assert main(["gen", str(SAMPLE), "--target", "markdown", "-o", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [".earl-trace.json", "specification.md"]  # + source map
    text = (tmp_path / "specification.md").read_text()
    assert text.startswith("# PickAndPlace: specification\n")
    assert '<a id="manip-a-cs-fsm-idle-jointMove-t"></a>' in text
    assert "| [task/a](#task-a) | CT | purely computational agent | 1 | 0 | 0 | 0 | 0 | 4 |" in text


def test_markdown_cells_are_escaped() -> None:
    assert escape_markdown("a|b *c* _d_ <e>") == r"a\|b \*c\* \_d\_ \<e\>"
    assert escape_markdown("two\nlines") == "two lines"
    assert code_span("a ∨ b|c") == r"`a ∨ b\|c`"
    assert code_span("x`y") == "``x`y``"
    assert code_span("") == ""

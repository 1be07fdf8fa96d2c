"""The regenerated paper tables of the sample, cell by cell, against the paper's content as
docs/earl-metamodel.md §5 (the working summary of the paper) states it: Table 6 (initial
conditions of the transitions, terminal conditions of the behaviours of manip/a.cs) and
Table 7 (which pf of which stage of each behaviour's tf writes which memory and output
buffer). Checked in the HTML report and in the markdown target."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from lxml import html

from earl_m2t.api import load
from earl_m2t.gen import render
from earl_m2t.model.elements import EarlModel
from earl_m2t.report.page import render_report

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"

# -- transcribed from earl-metamodel.md §5 ---------------------------------------------------
# "Transitions: idle→jointMove and jointMove→jointMove: newJointPos ∧ ¬emergencyStop;
#  idle→operationalMove and operationalMove→operationalMove: newOperationalPos ∧ ¬emergencyStop;
#  jointMove→idle, operationalMove→idle: ¬emergencyStop; every other state→emergencyStop: emergencyStop."
TABLE6_TRANSITIONS = {
    ("idle", "jointMove"): "newJointPos ∧ ¬emergencyStop",
    ("jointMove", "jointMove"): "newJointPos ∧ ¬emergencyStop",
    ("idle", "operationalMove"): "newOperationalPos ∧ ¬emergencyStop",
    ("operationalMove", "operationalMove"): "newOperationalPos ∧ ¬emergencyStop",
    ("jointMove", "idle"): "¬emergencyStop",
    ("operationalMove", "idle"): "¬emergencyStop",
    ("idle", "emergencyStop"): "emergencyStop ∨ inError()",
    ("jointMove", "emergencyStop"): "emergencyStop ∨ inError()",
    ("operationalMove", "emergencyStop"): "emergencyStop ∨ inError()",
}
# "Terminal conditions: idle: newJointPos ∨ newOperationalPos ∨ emergencyStop;
#  jointMove, operationalMove: motionFinished ∨ emergencyStop; emergencyStop: false."
TABLE6_TERMINAL = {
    "idle/bb": "newJointPos ∨ newOperationalPos ∨ emergencyStop",
    "jointMove/bb": "motionFinished ∨ emergencyStop",
    "operationalMove/bb": "motionFinished ∨ emergencyStop",
    "emergencyStop/bb": "false",
}
# Table 4 / eq. 5: the memory columns; "ManipulatorState ob", "MotorControllerCommandK ob".
TABLE7_MEMORY = ["motionFinished", "currentOperationalPos", "currentJointPos", "emergencyStopCommandK",
                 "windingCurrentK"]
TABLE7_OUTPUTS = ["ManipulatorState", "MotorControllerCommandK"]
# "every bb runs calculatePosition/pf (writes currentJointPos, currentOperationalPos) plus one of
#  passiveRegulation (idle; writes windingCurrentK), jointMove / operationalMove (write
#  motionFinished, windingCurrentK), emergencyStop (writes emergencyStopCommandK) – stage 1; then
#  outputManipState/pf (writes ManipulatorState ob) and outputMotorCon/pf (writes
#  MotorControllerCommandK ob) – stage 2."
_STAGE2 = {("outputManipState/pf", 2): {"ManipulatorState"}, ("outputMotorCon/pf", 2): {"MotorControllerCommandK"}}
_POSITION = {("calculatePosition/pf", 1): {"currentJointPos", "currentOperationalPos"}}
TABLE7 = {
    "idle/bb": {**_POSITION, ("passiveRegulation/pf", 1): {"windingCurrentK"}, **_STAGE2},
    "jointMove/bb": {**_POSITION, ("jointMove/pf", 1): {"motionFinished", "windingCurrentK"}, **_STAGE2},
    "operationalMove/bb": {**_POSITION, ("operationalMove/pf", 1): {"motionFinished", "windingCurrentK"}, **_STAGE2},
    "emergencyStop/bb": {**_POSITION, ("emergencyStop/pf", 1): {"emergencyStopCommandK"}, **_STAGE2},
}
# ---------------------------------------------------------------------------------------------


def paper_form(condition: str) -> str:
    """The report writes ``newJointPos/pp``; the summary writes ``newJointPos``."""
    return re.sub(r"/pp(\.fun)?\b", "", " ".join(condition.split()))


def column(name: str) -> str:
    """Column names compare without the case of their first letter (``ManipulatorState``)."""
    return name[:1].lower() + name[1:]


Matrix = dict[str, dict[tuple[str, int], set[str]]]


def check_table6(transitions: dict[tuple[str, str], str], terminal: dict[str, str]) -> None:
    assert set(transitions) == set(TABLE6_TRANSITIONS)
    for key, expected in TABLE6_TRANSITIONS.items():
        assert paper_form(transitions[key]) == expected, key
    assert set(terminal) == set(TABLE6_TERMINAL)
    for bb, expected in TABLE6_TERMINAL.items():
        assert paper_form(terminal[bb]) == expected, bb


def check_table7(memory: list[str], outputs: list[str], marks: list[tuple[str, str, int, list[bool]]]) -> None:
    assert sorted(memory) == sorted(TABLE7_MEMORY)
    assert [column(c) for c in outputs] == [column(c) for c in TABLE7_OUTPUTS]
    columns = [column(c) for c in memory + outputs]
    found: Matrix = {}
    for bb, pf, stage, cells in marks:
        assert len(cells) == len(columns), (bb, pf)
        assert (pf, stage) not in found.setdefault(bb, {}), (bb, pf)
        found[bb][(pf, stage)] = set()
        for name, mark in zip(columns, cells):
            expected = name in {column(c) for c in TABLE7[bb].get((pf, stage), set())}
            assert mark == expected, f"{bb} {pf} stage {stage} column {name}: {'•' if mark else 'empty'}"
    assert {bb: set(rows) for bb, rows in found.items()} == {bb: set(rows) for bb, rows in TABLE7.items()}


@pytest.fixture(scope="module")
def model() -> EarlModel:
    return load(SAMPLE).model


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz dot is missing (./dev installs graphviz)")
def test_the_report_tables_of_manip_cs_are_the_papers(model: EarlModel) -> None:
    page = html.fromstring(render_report(model, [])["index.html"])
    section = page.get_element_by_id("manip-a-cs")
    tables = {t.getprevious().text_content().strip(): t for t in section.iter("table")
              if t.getprevious() is not None and t.getprevious().tag == "h4"}
    transitions = {}
    for row in tables["Transition conditions (Table 6)"].findall("tr")[1:]:
        cells = [td.text_content().strip() for td in row.findall("td")]
        transitions[(cells[1], cells[2])] = cells[3]
    terminal = {}
    for row in tables["Terminal and error conditions (Table 6)"].findall("tr")[1:]:
        cells = [td.text_content().strip() for td in row.findall("td")]
        terminal[cells[0]] = cells[2]
    check_table6(transitions, terminal)

    matrix = section.find_class("composition")[0]
    head = matrix.findall("tr")
    groups = {th.text_content().strip(): int(th.get("colspan")) for th in head[0].find_class("group")}
    names = [th.text_content().strip() for th in head[1].findall("th")]
    memory, outputs = names[:groups["/mo"]], names[groups["/mo"]:]
    assert len(outputs) == groups["/ob"]
    marks = []
    behaviour = ""
    for row in head[2:]:
        cells = [td.text_content().strip() for td in row.findall("td")]
        if len(cells) == 3 + len(names):
            behaviour, cells = cells[0], cells[1:]
        marks.append((behaviour, cells[1], int(cells[0]), [c == "•" for c in cells[2:]]))
    check_table7(memory, outputs, marks)


def test_the_markdown_tables_of_manip_cs_are_the_papers(model: EarlModel) -> None:
    text = render(model, "markdown").generated["specification.md"].decode()
    section = text.split('<a id="manip-a-cs"></a>', 1)[1].split("\n### ", 1)[0]

    def table(title: str) -> list[list[str]]:
        blocks = section.split(title, 1)[1].split("\n\n")
        block = next(b.strip() for b in blocks if b.strip().startswith("|"))
        rows = [re.split(r"(?<!\\)\|", line.strip())[1:-1] for line in block.splitlines()]
        return [[re.sub(r"<a id=\"[^\"]*\"></a>", "", c).strip().strip("`").replace("\\", "") for c in row]
                for row in rows]

    transitions = {(r[1], r[2]): r[3] for r in table("Transitions (Table 6)")[2:]}
    terminal = {r[0]: r[1] for r in table("Terminal and error conditions (Table 6)")[2:]}
    check_table6(transitions, terminal)

    rows = table("Transition function composition (Table 7): what each pf writes")
    names = rows[0][3:]
    memory = [n.removesuffix("/mo") for n in names if n.endswith("/mo")]
    outputs = [n.removesuffix("/ob") for n in names if n.endswith("/ob")]
    assert len(memory) + len(outputs) == len(names)
    check_table7(memory, outputs, [(r[0], r[2], int(r[1]), [c == "•" for c in r[3:]]) for r in rows[2:]])

"""``earl-m2t stats``: the counts, their definitions, the output formats and the exit codes."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest
from lxml import etree

from earl_m2t.api import load
from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.loader import load_raw_model
from earl_m2t.resources import metamodel_path
from earl_m2t.stats import COUNTS, Stats, model_stats, parse_definitions, stats_definitions

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
BAD = ROOT / "tests" / "fixtures" / "bad"
CORPUS = ROOT.parent / "shared" / "corpus"

# B/P/Po/C/SM/T/A of the corpus README ("SysML v1 XMI files" and "Other" tables); the `-model.xmi`
# rows are the same models as the `.mdzip` rows above them.
README_FIGURES: dict[str, tuple[int, int, int, int, int, int, int]] = {
    "papyrus/electric-kettle-sysml16.uml": (4, 0, 57, 0, 4, 18, 9),
    "papyrus/transmission-system-sysml16.uml": (6, 0, 109, 0, 3, 24, 1),
    "papyrus/arrowhead-principles-sysml16.uml": (38, 0, 0, 0, 0, 0, 0),
    "papyrus/arrowhead-5.0-dsl-sysml16.uml": (5, 0, 327, 16, 1, 3, 2),
    "papyrus/robotml-robocab-sysml-papyrus07.uml": (0, 5, 66, 39, 2, 18, 0),
    "papyrus/incose-vehicle-parametrics-papyrus07.uml": (6, 7, 0, 7, 0, 0, 0),
    "other/papyrus-uml-marte-no-sysml-producer-consumer.uml": (0, 9, 3, 2, 0, 0, 0),
    "cameo/mtconnect-v2.6-cameo2024x.mdzip": (957, 1598, 24, 76, 6, 55, 8),
    "cameo/mtconnect-v2.6-cameo2024x-model.xmi": (957, 1598, 24, 76, 6, 55, 8),
    "cameo/capella-bridge-statemodes-md19.mdzip": (0, 0, 0, 0, 1, 5, 4),
    "cameo/capella-bridge-activities-md19.mdzip": (4, 3, 0, 0, 0, 0, 5),
    "cameo/arrowhead-tank-control-md19.mdzip": (0, 75, 72, 38, 0, 0, 0),
    "cameo/arrowhead-tank-control-md19-model.xmi": (0, 75, 72, 38, 0, 0, 0),
    "cameo/cameo-to-capella-md-emf-uml2-export.uml": (10, 31, 16, 24, 1, 6, 5),
    "ea/mtconnect-2019-ea-sysml15.xml": (205, 70, 0, 0, 2, 18, 0),
}
# Figures the README gives in its notes: requirements and value types.
README_NOTES: dict[str, dict[str, int]] = {
    "papyrus/electric-kettle-sysml16.uml": {"requirements": 15},
    "papyrus/transmission-system-sysml16.uml": {"requirements": 14},
    "papyrus/arrowhead-principles-sysml16.uml": {"requirements": 11},
    "cameo/mtconnect-v2.6-cameo2024x.mdzip": {"value_types": 136},
    "cameo/mtconnect-v2.6-cameo2024x-model.xmi": {"value_types": 136},
    "cameo/cameo-to-capella-md-emf-uml2-export.uml": {"requirements": 5},
    "ea/mtconnect-2019-ea-sysml15.xml": {"value_types": 15},
}
PAPYRUS_ONLY = ("papyrus/", "other/")  # Eclipse UML2 files, which the reader must read today

JSON_KEYS = {"format", "file", "dialect", "file_size", "elements", "counts", "stereotype_applications", "earl"}


def earl_m2t(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)


def seven(stats: Stats) -> tuple[int, int, int, int, int, int, int]:
    return (stats.blocks, stats.parts, stats.ports, stats.connectors, stats.state_machines, stats.transitions,
            stats.activities)


# -- the sample, counted independently with lxml --------------------------------------------------

XMI = "http://www.omg.org/spec/XMI/20131001"
SYSML_PAPYRUS = "http://www.eclipse.org/papyrus/sysml/"
EARL_PAPYRUS = "http:///schemas/EARL/"
IMPLICIT = {"ownedAttribute": "Property", "ownedConnector": "Connector", "transition": "Transition"}


def lxml_counts(path: Path) -> dict[str, int]:
    """The README definitions written again from scratch, for a Papyrus file."""
    root = etree.parse(str(path)).getroot()
    definitions: dict[str, etree._Element] = {}
    model = root.find("{http://www.eclipse.org/uml2/5.0.0/UML}Model")
    assert model is not None
    stack = [model]
    while stack:
        el = stack.pop()
        if el.tag == f"{{{XMI}}}Extension":
            continue
        if el.get(f"{{{XMI}}}id"):
            definitions[el.get(f"{{{XMI}}}id")] = el
        stack.extend(child for child in el if isinstance(child.tag, str))

    def uml_type(el: etree._Element) -> str:
        declared = el.get(f"{{{XMI}}}type")
        if declared:
            return str(declared).split(":")[-1]
        return "Model" if el is model else IMPLICIT.get(str(el.tag), "")

    types = Counter(uml_type(el) for el in definitions.values())
    applications = [el for el in root
                    if isinstance(el.tag, str) and el is not model and el.tag != f"{{{XMI}}}Documentation"]

    def sysml(name: str, base: str, metaclasses: set[str]) -> int:
        return sum(
            1 for el in applications
            if str(etree.QName(el).namespace).startswith(SYSML_PAPYRUS) and etree.QName(el).localname.lower() == name
            and el.get(base) in definitions and uml_type(definitions[el.get(base)]) in metaclasses
        )

    return {
        "elements": len(definitions),
        "blocks": sysml("block", "base_Class", {"Class", "AssociationClass"}),
        "parts": sum(1 for el in definitions.values()
                     if el.tag == "ownedAttribute" and uml_type(el) == "Property"
                     and el.get("aggregation") == "composite"),
        "ports": types["Port"],
        "connectors": types["Connector"],
        "state_machines": types["StateMachine"],
        "transitions": types["Transition"],
        "activities": types["Activity"],
        "requirements": sysml("requirement", "base_Class", {"Class"}),
        "value_types": sysml("valuetype", "base_DataType", {"DataType", "Enumeration", "PrimitiveType"}),
        "data_types": types["DataType"] + types["Enumeration"] + types["PrimitiveType"],
        "packages": types["Package"] + types["Model"] + types["Profile"],
        "stereotypes_sysml": sum(1 for el in applications if str(etree.QName(el).namespace).startswith(SYSML_PAPYRUS)),
        "stereotypes_earl": sum(1 for el in applications if str(etree.QName(el).namespace).startswith(EARL_PAPYRUS)),
    }


def test_the_sample_counts_agree_with_a_direct_lxml_count_of_the_file() -> None:
    expected = lxml_counts(SAMPLE)
    stats = model_stats(load_raw_model(SAMPLE))
    assert {key: getattr(stats, key) for key in expected} == expected
    assert stats.stereotypes_other == 0
    # the figures are not all zero: the sample has blocks, parts, ports, connectors, machines, activities
    assert min(expected[k] for k in ("blocks", "parts", "ports", "connectors", "state_machines", "transitions",
                                     "activities")) > 0


def test_the_sample_earl_figures_are_those_of_the_lifted_model() -> None:
    model = load(SAMPLE).model
    stats = model_stats(load_raw_model(SAMPLE), earl=model)
    assert stats.earl is not None
    assert (stats.earl.agents, stats.earl.subsystems, stats.earl.links) == (
        len(model.agents), len(model.subsystems), len(model.links))
    assert stats.earl.agents == 3  # task/a, manip/a, grip/a


# -- the definitions, on a small handmade file ------------------------------------------------------

SMALL = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001"
    xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML"
    xmlns:Blocks="http://www.eclipse.org/papyrus/sysml/1.6/SysML/Blocks"
    xmlns:Requirements="http://www.eclipse.org/papyrus/sysml/1.6/SysML/Requirements"
    xmlns:DSL="http://www.example.org/dsl">
  <uml:Model xmi:id="m" name="M">
    <packagedElement xmi:type="uml:Package" xmi:id="pk" name="P">
      <packagedElement xmi:type="uml:Class" xmi:id="a" name="A">
        <ownedAttribute xmi:id="pa" name="b" type="b" aggregation="composite"/>
        <ownedAttribute xmi:type="uml:Property" xmi:id="pr" name="r" type="b"/>
        <ownedAttribute xmi:type="uml:Port" xmi:id="po" name="p" aggregation="composite"/>
        <ownedConnector xmi:id="k" name="k"/>
      </packagedElement>
      <packagedElement xmi:type="uml:Class" xmi:id="b" name="B"/>
      <packagedElement xmi:type="uml:AssociationClass" xmi:id="ab" name="AB"/>
      <packagedElement xmi:type="uml:Class" xmi:id="d" name="DslBlock"/>
      <packagedElement xmi:type="uml:Class" xmi:id="r" name="Req"/>
      <packagedElement xmi:type="uml:DataType" xmi:id="vt" name="Speed"/>
      <packagedElement xmi:type="uml:Enumeration" xmi:id="en" name="Mode"/>
      <packagedElement xmi:type="uml:Association" xmi:id="as" memberEnd="pa oe">
        <ownedEnd xmi:type="uml:Property" xmi:id="oe" type="a" aggregation="composite"/>
      </packagedElement>
    </packagedElement>
    <xmi:Extension extender="tool"><packagedElement xmi:type="uml:Port" xmi:id="copy"/></xmi:Extension>
  </uml:Model>
  <Blocks:Block xmi:id="s1" base_Class="a"/>
  <Blocks:block xmi:id="s2" base_Class="b"/>
  <Blocks:Block xmi:id="s3" base_Class="ab"/>
  <Blocks:Block xmi:id="s4" base_Class="elsewhere"/>
  <DSL:Block xmi:id="s5" base_Class="d"/>
  <Requirements:Requirement xmi:id="s6" base_Class="r" base_NamedElement="r"/>
  <Blocks:ValueType xmi:id="s7" base_DataType="vt"/>
  <Blocks:ValueType xmi:id="s8" base_DataType="en"/>
</xmi:XMI>
"""


@pytest.fixture
def small(tmp_path: Path) -> Path:
    path = tmp_path / "small.uml"
    path.write_text(SMALL, encoding="utf-8")
    return path


def test_the_definitions_of_the_corpus_readme_hold_on_a_small_handmade_model(small: Path) -> None:
    stats = model_stats(load_raw_model(small))
    assert stats.counts() == {
        "blocks": 3,        # any case, association blocks too; not a DSL 'Block', not a base outside the file
        "parts": 1,         # a composite ownedAttribute without xmi:type; not the port, not the association end
        "ports": 1,         # not the copy inside xmi:Extension
        "connectors": 1,    # written without xmi:type
        "state_machines": 0,
        "transitions": 0,
        "activities": 0,
        "requirements": 1,  # one application carrying base_Class and base_NamedElement
        "value_types": 2,   # on a DataType and on an Enumeration
        "data_types": 2,
        "packages": 2,      # the Model and the Package
    }
    assert stats.stereotype_applications() == {"sysml": 7, "earl": 0, "other": 1}
    assert stats.elements == 15  # the copy inside xmi:Extension is not a definition


def test_a_definitions_file_that_leaves_a_count_out_is_rejected() -> None:
    text = metamodel_path("stats.toml").read_text(encoding="utf-8").replace("activities =", "behaviours =")
    with pytest.raises(ValueError, match=r"\[types\]"):
        parse_definitions(text)
    assert set(stats_definitions().types) | {"parts"} | set(stats_definitions().stereotypes) == set(COUNTS)


# -- the corpus ------------------------------------------------------------------------------------

def _corpus_file(relative: str) -> Path:
    if not CORPUS.is_dir():
        pytest.skip("shared corpus not beside the checkout")
    path = CORPUS / relative
    assert path.is_file(), f"{relative} is listed in the corpus README but missing"
    return path


def test_every_papyrus_file_of_the_corpus_has_readme_figures_here() -> None:
    if not CORPUS.is_dir():
        pytest.skip("shared corpus not beside the checkout")
    present = {f"papyrus/{p.name}" for p in (CORPUS / "papyrus").iterdir() if p.is_file()}
    assert present and present <= set(README_FIGURES)


@pytest.mark.parametrize("relative", [r for r in README_FIGURES if r.startswith(PAPYRUS_ONLY)])
def test_papyrus_corpus_files_give_the_figures_of_the_corpus_readme(relative: str) -> None:
    stats = model_stats(load_raw_model(_corpus_file(relative)))
    assert seven(stats) == README_FIGURES[relative]
    for key, value in README_NOTES.get(relative, {}).items():
        assert getattr(stats, key) == value, key


@pytest.mark.parametrize("relative", [r for r in README_FIGURES if not r.startswith(PAPYRUS_ONLY)])
def test_cameo_and_ea_corpus_files_give_the_readme_figures_once_the_reader_accepts_them(relative: str) -> None:
    path = _corpus_file(relative)
    try:
        raw = load_raw_model(path)
    except ModelReadError as exc:
        pytest.skip(f"not readable yet: {exc.one_line()}")
    stats = model_stats(raw)
    assert seven(stats) == README_FIGURES[relative]
    for key, value in README_NOTES.get(relative, {}).items():
        assert getattr(stats, key) == value, key


def test_dsl_stereotypes_are_counted_as_other_and_not_as_sysml_blocks_or_ports() -> None:
    stats = model_stats(load_raw_model(_corpus_file("papyrus/robotml-robocab-sysml-papyrus07.uml")))
    assert stats.blocks == 0 and stats.stereotypes_sysml == 0 and stats.stereotypes_other > 0


# -- the command line ------------------------------------------------------------------------------

def test_json_output_has_the_documented_keys() -> None:
    result = earl_m2t("stats", "--format", "json", str(SAMPLE))
    assert result.returncode == 0, result.stderr
    document = json.loads(result.stdout)
    assert set(document) == JSON_KEYS
    assert document["format"] == 1 and document["dialect"] == "papyrus"
    assert document["file_size"] == SAMPLE.stat().st_size
    assert list(document["counts"]) == list(COUNTS)
    assert list(document["stereotype_applications"]) == ["sysml", "earl", "other"]
    assert set(document["earl"]) == {"agents", "subsystems", "links"}
    assert document["counts"] == {key: value for key, value in lxml_counts(SAMPLE).items() if key in COUNTS}


def test_json_says_earl_null_for_a_model_without_earl(small: Path) -> None:
    result = earl_m2t("stats", "--format", "json", str(small))
    assert result.returncode == 0, result.stderr
    document = json.loads(result.stdout)
    assert set(document) == JSON_KEYS and document["earl"] is None and document["counts"]["blocks"] == 3


def test_text_output_is_an_aligned_two_column_table() -> None:
    result = earl_m2t("stats", str(SAMPLE))
    assert result.returncode == 0 and result.stderr == ""
    rows = [re.fullmatch(r"(\S.*?\S) {2,}(\S.*)", line) for line in result.stdout.splitlines()]
    assert all(rows), result.stdout
    assert len({row.start(2) for row in rows if row}) == 1  # every value starts in the same column
    values = {row[1]: row[2] for row in rows if row}
    assert list(values)[:2] == ["file", "dialect"]
    assert values["dialect"] == "papyrus" and values["EARL model"] == "yes" and values["EARL agents"] == "3"
    counted = lxml_counts(SAMPLE)
    assert values["blocks"] == str(counted["blocks"]) and values["state machines"] == str(counted["state_machines"])


@pytest.mark.parametrize("name", ["malformed.uml", "not-xmi.xml", "no-such-file.uml"])
def test_an_unreadable_file_is_one_line_on_stderr_and_exit_2(name: str) -> None:
    result = earl_m2t("stats", str(BAD / name))
    assert result.returncode == 2
    assert result.stdout == ""
    assert len(result.stderr.splitlines()) == 1 and ": error: " in result.stderr

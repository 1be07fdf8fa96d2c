"""The profile's «LtlProperty» constraint (``metadata NAME : Ltl { formula = "…"; }`` in SysML v2):
the bundled sample carries the emergency-stop property in every dialect and ``verify`` proves it
without ``--ltl``, with the real SPIN; a broken or mistyped property points at its constraint."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.cli.app import main
from tests.diff.variants import with_model_comment

ROOT = Path(__file__).resolve().parents[1]
SAMPLE_DIR = ROOT / "samples" / "pick_and_place"
ESTOP = "[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)"
SAMPLES = {
    "papyrus": SAMPLE_DIR / "pick_and_place.uml",
    "cameo": SAMPLE_DIR / "pick_and_place.cameo.xmi",
    "ea": SAMPLE_DIR / "pick_and_place.ea.xml",
    "sysml": SAMPLE_DIR / "pick_and_place.sysml",
}


def _verify(path: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, dict]:
    code = main(["verify", str(path), "--format", "json"])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("dialect", sorted(SAMPLES))
def test_the_sample_carries_the_emergency_stop_property(dialect: str) -> None:
    (prop,) = load(SAMPLES[dialect]).properties
    assert (prop.label, prop.text) == ("estopLatches", ESTOP)
    line = SAMPLES[dialect].read_bytes().splitlines()[prop.location.line - 1].decode("cp1252")
    assert "manip/a.cs@emergencyStop" in line, (dialect, prop.location)


@pytest.mark.parametrize("dialect", sorted(SAMPLES))
def test_verify_proves_the_samples_property_without_ltl(dialect: str, capsys: pytest.CaptureFixture[str]) -> None:
    code, result = _verify(SAMPLES[dialect], capsys)
    assert code == 0, result
    assert result["findings"] == [] and result["not_proven"] == []
    assert f"{ESTOP} holds" in result["proven"]


def _changed(dialect: str, tmp_path: Path, formula: str) -> Path:
    """The sample with its property's formula replaced (written as the dialect writes it)."""
    sample = SAMPLES[dialect]
    encoding = "cp1252" if dialect == "ea" else "utf-8"
    text = sample.read_text(encoding=encoding)
    written = ESTOP if dialect == "sysml" or dialect == "papyrus" else ESTOP.replace(">", "&gt;")
    replacement = formula if dialect == "sysml" or dialect == "papyrus" else formula.replace(">", "&gt;")
    assert written in text
    path = tmp_path / sample.name
    path.write_text(text.replace(written, replacement), encoding=encoding)
    return path


@pytest.mark.parametrize("dialect", ["papyrus", "sysml"])
def test_a_violated_property_points_at_its_constraint(dialect: str, tmp_path: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    path = _changed(dialect, tmp_path, "[] (manip/a.cs@idle -> [] manip/a.cs@idle)")
    code, result = _verify(path, capsys)
    assert code == 1
    (finding,) = result["findings"]
    assert finding["code"] == "V005" and finding["element"] == "estopLatches"
    assert finding["trace"], finding
    assert "manip/a.cs@idle" in path.read_text(encoding="utf-8").splitlines()[finding["line"] - 1]


def _error_at(path: Path, capsys: pytest.CaptureFixture[str], marker: str) -> tuple[int, str, int, int]:
    """verify's exit code and stderr for ``path``, and the line and column of ``marker`` in the file."""
    code = main(["verify", str(path)])
    err = capsys.readouterr().err
    lines = path.read_text(encoding="utf-8").splitlines()
    line = next(i for i, text in enumerate(lines, 1) if marker in text)
    return code, err, line, lines[line - 1].index(marker) + 1


def test_an_unknown_predicate_in_the_sysml_constraint_is_one_line_at_its_column(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _changed("sysml", tmp_path, "[] (manip/a.cs@emergencyStop -> manip/a.cs.halted/pp)")
    code, err, line, column = _error_at(path, capsys, "manip/a.cs.halted/pp")
    assert code == 2
    assert err.startswith(f"earl-m2t: verify: {path}:{line}:{column}: no primitive predicate halted/pp "
                          "of the subsystem manip/a.cs"), err
    assert len(err.splitlines()) == 1


def test_a_syntax_error_in_the_papyrus_constraint_is_one_line(tmp_path: Path,
                                                             capsys: pytest.CaptureFixture[str]) -> None:
    path = _changed("papyrus", tmp_path, "[] (manip/a.cs@emergencyStop => manip/a.cs@idle)")
    code, err, line, column = _error_at(path, capsys, "=> manip")
    assert code == 2
    assert err.startswith(f"earl-m2t: verify: {path}:{line}:{column}: unexpected '=>"), err
    assert len(err.splitlines()) == 1


def test_convert_keeps_the_property_as_ltl_metadata(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    converted = tmp_path / "converted.sysml"
    assert main(["convert", str(SAMPLES["papyrus"]), "--to", "sysml", "-o", str(converted)]) == 0
    capsys.readouterr()
    assert f'metadata estopLatches : Ltl {{ formula = "{ESTOP}"; }}' in converted.read_text(encoding="utf-8")
    code, result = _verify(converted, capsys)
    assert code == 0 and f"{ESTOP} holds" in result["proven"]


def test_a_constraint_without_a_formula_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    sample = SAMPLES["papyrus"].read_text(encoding="utf-8")
    path = tmp_path / "empty.uml"
    path.write_text(sample.replace(f"<body>{ESTOP}</body>", "<body></body>"), encoding="utf-8")
    code = main(["verify", str(path)])
    err = capsys.readouterr().err
    line = next(i for i, text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1) if "<body></body>" in text)
    assert code == 2
    assert err == f"earl-m2t: verify: {path}:{line}:1: the property estopLatches has no formula\n"


@pytest.mark.parametrize(("body", "formula"), [
    # Papyrus: the comment's text as written
    ("<body>earl-m2t: ltl eventually: &lt;&gt; task/a.cs@supervise</body>", "<> task/a.cs@supervise"),
    ("<body>earl-m2t: ltl same: [] (manip/a.cs@idle &lt;-&gt; manip/a.cs@idle)</body>",
     "[] (manip/a.cs@idle <-> manip/a.cs@idle)"),
    # an HTML note (Enterprise Architect): the tags go, the escaped operator stays
    ("<body>&lt;p&gt;earl-m2t: ltl eventually: &amp;lt;&amp;gt; task/a.cs@supervise&lt;/p&gt;</body>",
     "<> task/a.cs@supervise"),
])
def test_a_comment_directive_keeps_the_ltl_operators_that_look_like_markup(body: str, formula: str,
                                                                           tmp_path: Path) -> None:
    """``<>`` (eventually) and ``<->`` are no HTML tags: the formula reaches verify whole."""
    path = tmp_path / "model.uml"
    path.write_text(with_model_comment(SAMPLES["papyrus"].read_text(encoding="utf-8"), "_ltl", body),
                    encoding="utf-8")
    assert [p.text for p in load(path).properties][1:] == [formula]


@pytest.mark.parametrize("dialect", sorted(SAMPLES))
def test_show_lists_the_models_properties(dialect: str, capsys: pytest.CaptureFixture[str]) -> None:
    (prop,) = load(SAMPLES[dialect]).properties
    assert main(["show", str(SAMPLES[dialect])]) == 0
    text = capsys.readouterr().out
    assert text.endswith(f"ltl properties\n  estopLatches: {ESTOP}  (line {prop.location.line})\n")
    assert main(["show", str(SAMPLES[dialect]), "--format", "json"]) == 0
    shown = json.loads(capsys.readouterr().out)["ltl_properties"]
    assert shown == [{"name": "estopLatches", "formula": ESTOP, "file": str(SAMPLES[dialect]),
                      "line": prop.location.line}]

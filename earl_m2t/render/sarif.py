"""``check --format sarif``: SARIF 2.1.0, as GitHub code scanning and other SARIF viewers read it.

One run; ``tool.driver.rules`` describes every rule of the run with its page as help text;
each finding is a result pointing into the model file (a path relative to the repository
root, ``%SRCROOT%``) and at its element (a logical location). Unreadable files are
``toolExecutionNotifications`` of the invocation. The output has no timestamps and is sorted,
so the same input gives the same bytes.
"""

from __future__ import annotations

import hashlib
import json
from collections import Counter
from pathlib import Path
from typing import Any
from urllib.parse import quote

from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.render._ci import exit_code, ordered, repo_path, rule_codes, rule_info
from earl_m2t.render.check_report import CheckReport

SARIF_VERSION = "2.1.0"
SARIF_SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
SRCROOT = "%SRCROOT%"
FINGERPRINT_KEY = "earlFinding/v1"

LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def render_sarif(report: CheckReport, base: Path | None = None) -> str:
    document = sarif_document(report, base)
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


def sarif_document(report: CheckReport, base: Path | None = None) -> dict[str, Any]:
    from earl_m2t.version import __version__

    codes = rule_codes(report)
    index = {code: position for position, code in enumerate(codes)}
    code = exit_code(report)
    invocation: dict[str, Any] = {"executionSuccessful": not report.unreadable, "exitCode": code}
    if code:
        invocation["exitCodeDescription"] = "model files could not be read" if code == 2 else "error findings"
    notifications = [_notification(item, base) for item in report.unreadable]
    if notifications:
        invocation["toolExecutionNotifications"] = notifications
    driver = {
        "name": "earl-m2t",
        "fullName": "earl-m2t check",
        "version": __version__,
        "semanticVersion": __version__,
        "rules": [_rule(code) for code in codes],
    }
    return {
        "$schema": SARIF_SCHEMA,
        "version": SARIF_VERSION,
        "runs": [
            {
                "tool": {"driver": driver},
                "invocations": [invocation],
                "results": _results(report.diagnostics, index, base),
                "columnKind": "unicodeCodePoints",
                "properties": {
                    "checked": [repo_path(file, base)[0] for file in report.checked],
                },
            }
        ],
    }


def _rule(code: str) -> dict[str, Any]:
    info = rule_info(code)
    if info is None:  # a rule outside the catalogue: only its code is known
        return {"id": code, "name": code, "shortDescription": {"text": code}}
    page = info.doc().strip()
    lead = _lead(page) or info.summary
    return {
        "id": code,
        "name": info.name,
        "shortDescription": {"text": info.summary, "markdown": info.summary},
        "fullDescription": {"text": lead, "markdown": lead},
        "help": {"text": page, "markdown": page},
        "defaultConfiguration": {"level": LEVELS[info.severity]},
        "properties": {
            "source": info.source,
            "engine": info.engine,
        },
    }


def _lead(page: str) -> str:
    """The paragraph below the page's title: what the rule is about in one or two sentences."""
    lines = page.splitlines()
    body = lines[1:] if lines and lines[0].startswith("# ") else lines
    paragraph: list[str] = []
    for line in body:
        if line.startswith("#"):
            break
        if not line.strip():
            if paragraph:
                break
            continue
        paragraph.append(line.strip())
    return " ".join(paragraph)


def _artifact(file: str, base: Path | None) -> dict[str, Any]:
    path, relative = repo_path(file, base)
    if relative:
        return {"uri": quote(path), "uriBaseId": SRCROOT}
    return {"uri": Path(path).as_uri() if Path(path).is_absolute() else quote(path)}


def _physical(file: str, line: int, base: Path | None) -> dict[str, Any]:
    # a finding's column is the column in a condition's text, not in the file: no startColumn
    return {"artifactLocation": _artifact(file, base), "region": {"startLine": max(line, 1)}}


def _results(diagnostics: list[Diagnostic], index: dict[str, int], base: Path | None) -> list[dict[str, Any]]:
    results = []
    occurrences: Counter[str] = Counter()
    for diag in ordered(diagnostics):
        loc = diag.location
        location: dict[str, Any] = {"physicalLocation": _physical(loc.file, loc.line, base)}
        if diag.element:
            location["logicalLocations"] = [{"name": diag.element.rsplit(".", 1)[-1],
                                             "fullyQualifiedName": diag.element, "kind": "element"}]
        identity = "\0".join((diag.code, repo_path(loc.file, base)[0], diag.element, diag.message))
        occurrences[identity] += 1
        digest = hashlib.sha256(identity.encode("utf-8")).hexdigest()[:32]
        result: dict[str, Any] = {
            "ruleId": diag.code,
            "ruleIndex": index[diag.code],
            "level": LEVELS[diag.severity],
            "message": {"text": diag.message},
            "locations": [location],
            "partialFingerprints": {FINGERPRINT_KEY: f"{digest}:{occurrences[identity]}"},
        }
        properties = {key: value for key, value in (("xmiId", loc.xmi_id), ("conditionColumn", loc.column)) if value}
        if properties:
            result["properties"] = properties
        results.append(result)
    return results


def _notification(item: dict[str, object], base: Path | None) -> dict[str, Any]:
    file = str(item.get("file", ""))
    line = item.get("line", 0)
    notification: dict[str, Any] = {
        "level": "error",
        "message": {"text": f"{file}: {item.get('message', 'cannot be read')}"},
        "descriptor": {"id": "model-unreadable"},
    }
    if file:
        physical: dict[str, Any] = {"artifactLocation": _artifact(file, base)}
        if isinstance(line, int) and line > 0:
            physical["region"] = {"startLine": line}
        notification["locations"] = [{"physicalLocation": physical}]
    return notification

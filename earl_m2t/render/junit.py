"""``check --format junit``: JUnit XML, as CI test-report viewers read it.

One ``testsuite`` per file, one ``testcase`` per rule of the run (``classname`` the file,
``name`` the code and rule name): it fails, with one ``failure`` listing the rule's findings
in that file, or it passes. A file that cannot be read is a suite with one errored testcase.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections import defaultdict

from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.render._ci import files_of, ordered, rule_codes, rule_title
from earl_m2t.render.check_report import CheckReport

UNREADABLE_CASE = "model-unreadable"

# characters XML 1.0 cannot carry at all, even escaped
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


def _xml_text(text: str) -> str:
    return _NOT_XML.sub("\ufffd", text)


def _finding_line(diag: Diagnostic) -> str:
    loc = diag.location
    where = f"{loc.file}:{loc.line}" if loc.line else loc.file
    element = f" [{diag.element}]" if diag.element else ""
    return _xml_text(f"{where}: {diag.code} {diag.severity.value}: {diag.message}{element}")


def render_junit(report: CheckReport) -> str:
    codes = rule_codes(report)
    findings: dict[tuple[str, str], list[Diagnostic]] = defaultdict(list)
    for diag in ordered(report.diagnostics):
        findings[(diag.location.file, diag.code)].append(diag)
    unreadable = {str(item.get("file", "")): item for item in report.unreadable}

    root = ET.Element("testsuites", name="earl-m2t check")
    totals = {"tests": 0, "failures": 0, "errors": 0}
    for file in files_of(report):
        suite = ET.SubElement(root, "testsuite", name=_xml_text(file))
        counts = {"tests": 0, "failures": 0, "errors": 0}
        if file in unreadable:
            item = unreadable[file]
            case = ET.SubElement(suite, "testcase", classname=_xml_text(file), name=UNREADABLE_CASE)
            line = item.get("line", 0)
            where = f"{file}:{line}" if line else file
            message = _xml_text(str(item.get("message", "cannot be read")))
            error = ET.SubElement(case, "error", message=message, type="ModelReadError")
            error.text = _xml_text(f"{where}: error: {item.get('message', 'cannot be read')}")
            counts["tests"] += 1
            counts["errors"] += 1
        else:
            for code in codes:
                case = ET.SubElement(suite, "testcase", classname=_xml_text(file), name=_xml_text(rule_title(code)))
                counts["tests"] += 1
                found = findings.get((file, code))
                if not found:
                    continue
                worst = min((d.severity for d in found), key=lambda s: s.rank)
                by_severity = [f"{n} {s.value}" for s in Severity if (n := sum(d.severity is s for d in found))]
                noun = "finding" if len(found) == 1 else "findings"
                failure = ET.SubElement(case, "failure", message=f"{len(found)} {noun} ({', '.join(by_severity)})",
                                        type=worst.value)
                failure.text = "\n".join(_finding_line(d) for d in found)
                counts["failures"] += 1
        for key, value in counts.items():
            suite.set(key, str(value))
            totals[key] += value
        suite.set("skipped", "0")
    for key, value in totals.items():
        root.set(key, str(value))
    root.set("skipped", "0")
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"

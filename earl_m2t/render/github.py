"""``check --format github``: GitHub Actions workflow commands, one annotation per finding.

``::error file=F,line=L,title=CODE rule-name::message [element]`` (``warning`` and ``notice``
for the other severities), escaped as the Actions runner un-escapes them. No ``col``: the
column of a finding is the column in a condition's text, not in the file.
"""

from __future__ import annotations

from pathlib import Path

from earl_m2t.diagnostics import Severity
from earl_m2t.render._ci import ordered, repo_path, rule_title
from earl_m2t.render.check_report import CheckReport

COMMANDS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def escape_data(text: str) -> str:
    """The message part of a workflow command (``toCommandValue`` + ``escapeData`` of actions/toolkit)."""
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str) -> str:
    """A property value of a workflow command (``escapeProperty`` of actions/toolkit)."""
    return escape_data(text).replace(":", "%3A").replace(",", "%2C")


def command(name: str, properties: dict[str, str], message: str) -> str:
    props = ",".join(f"{key}={escape_property(value)}" for key, value in properties.items() if value)
    return f"::{name} {props}::{escape_data(message)}" if props else f"::{name}::{escape_data(message)}"


def render_github(report: CheckReport, base: Path | None = None) -> str:
    lines = []
    for item in report.unreadable:
        file = str(item.get("file", ""))
        line = item.get("line", 0)
        properties = {"file": repo_path(file, base)[0] if file else "",
                      "line": str(line) if isinstance(line, int) and line > 0 else "",
                      "title": "earl-m2t: model not read"}
        lines.append(command("error", properties, str(item.get("message", "cannot be read"))))
    for diag in ordered(report.diagnostics):
        loc = diag.location
        properties = {"file": repo_path(loc.file, base)[0], "line": str(loc.line) if loc.line > 0 else "",
                      "title": rule_title(diag.code)}
        element = f" [{diag.element}]" if diag.element else ""
        lines.append(command(COMMANDS[diag.severity], properties, diag.message + element))
    return "".join(line + "\n" for line in lines)

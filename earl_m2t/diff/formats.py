"""The changes between two models as text (one line per element, like ``diff``), Markdown
(a pull-request comment) and JSON (documented in docs/model-diff.md)."""

from __future__ import annotations

import difflib
import json
from collections import Counter
from dataclasses import dataclass
from pathlib import PurePosixPath
from typing import TYPE_CHECKING, Any

from earl_m2t.diff.compare import Change, FieldChange
from earl_m2t.element_tree.presentation import presentation

if TYPE_CHECKING:  # the generator is imported only when --affected asks for it
    from earl_m2t.diff.affected import AffectedFile

FORMAT_VERSION = 1
FORMATS = ("text", "markdown", "json")
_ORDER = ("renamed", "changed", "added", "removed")


@dataclass(frozen=True)
class Affected:
    """What ``--affected OUT_DIR --target T`` found."""

    out_dir: str
    target: str
    files: list[AffectedFile]


def render(changes: list[Change], old_label: str, new_label: str, fmt: str, affected: Affected | None = None) -> str:
    if fmt == "json":
        return to_json(changes, old_label, new_label, affected)
    if fmt == "markdown":
        return to_markdown(changes, old_label, new_label) + _affected_markdown(affected)
    return to_text(changes) + _affected_text(affected)


def _affected_text(affected: Affected | None) -> str:
    if affected is None or not affected.files:
        return ""
    return "\n" + "".join(f"{a.action:<9} {PurePosixPath(affected.out_dir, a.path)}\n" for a in affected.files)


def _affected_markdown(affected: Affected | None) -> str:
    if affected is None or not affected.files:
        return ""
    lines = ["", f"#### Files of {_code(affected.out_dir)} (target {affected.target})", ""]
    lines += [f"- {a.action} {_code(a.path)}" for a in affected.files]
    return "\n".join(lines) + "\n"


def summary(changes: list[Change]) -> str:
    counts = Counter(c.change for c in changes)
    return ", ".join(f"{counts[name]} {name}" for name in _ORDER if counts[name])


def _shown(value: str) -> str:
    return value if value else "(none)"


def _instances(change: Change) -> str:
    return f" (×{change.instances})" if change.instances > 1 else ""


def _headline(change: Change) -> str:
    if change.change == "renamed":
        return f"{change.kind} {change.old_path} → {change.path}{_instances(change)}"
    return f"{change.kind} {change.path}{_instances(change)}"


def _contents(change: Change) -> str:
    return ", ".join(f"{count} {presentation().plural(kind, count)}" for kind, count in change.contents)


def _field(change: Change, field: FieldChange) -> tuple[str, str]:
    """(label, value) of a field line: before → after, or the value of an added/removed element."""
    label = presentation().field_label(field.field)
    if change.change == "added":
        return label, field.new
    if change.change == "removed":
        return label, field.old
    return label, ""



def _is_long(field: FieldChange) -> bool:
    return "\n" in field.old or "\n" in field.new


def _line_diff(field: FieldChange) -> list[str]:
    lines = difflib.unified_diff(field.old.splitlines(), field.new.splitlines(), lineterm="", n=1)
    return [line for line in lines if not line.startswith(("---", "+++"))]


def to_text(changes: list[Change]) -> str:
    label = presentation().field_label
    out: list[str] = []
    for change in changes:
        line = f"{change.change:<8} {_headline(change)}"
        if change.contents:
            line += f" (with {_contents(change)})"
        out.append(line)
        for field in change.fields:
            shown, value = _field(change, field)
            if value:
                out.append(f"           {shown}: {value}")
            elif _is_long(field):
                out.append(f"           {label(field.field)}:")
                out.extend(f"             {line}" for line in _line_diff(field))
            else:
                out.append(f"           {label(field.field)}: {_shown(field.old)} → {_shown(field.new)}")
    return "".join(line + "\n" for line in out)


def _code(value: str) -> str:
    """A Markdown code span for a table cell."""
    value = _shown(value).replace("|", "\\|")
    fence = "``" if "`" in value else "`"
    return f"{fence}{value}{fence}" if fence == "`" else f"{fence} {value} {fence}"


def to_markdown(changes: list[Change], old_label: str, new_label: str) -> str:
    label = presentation().field_label
    out = ["### EARL model changes", "", f"{_code(old_label)} → {_code(new_label)}: "
           + (summary(changes) if changes else "no change"), ""]
    if not changes:
        return "\n".join(out)
    out += ["| change | element | details |", "|---|---|---|"]
    long_fields: list[tuple[Change, FieldChange]] = []
    for change in changes:
        element = (f"{change.kind} {_code(change.old_path)} → {_code(change.path)}" if change.change == "renamed"
                   else f"{change.kind} {_code(change.path)}") + _instances(change)
        details: list[str] = []
        for field in change.fields:
            shown, value = _field(change, field)
            if value:
                details.append(f"{shown}: {_code(value)}")
            elif _is_long(field):
                details.append(f"{label(field.field)}: changed (below)")
                long_fields.append((change, field))
            else:
                details.append(f"{label(field.field)}: {_code(field.old)} → {_code(field.new)}")
        if change.contents:
            details.append(f"with {_contents(change)}")
        out.append(f"| {change.change} | {element} | {'<br>'.join(details)} |")
    for change, field in long_fields:
        out += ["", f"<details><summary>{change.kind} <code>{change.path}</code>: {label(field.field)}</summary>",
                "", "```diff", *_line_diff(field), "```", "", "</details>"]
    return "\n".join(out) + "\n"


def to_json(changes: list[Change], old_label: str, new_label: str, affected: Affected | None = None) -> str:
    document: dict[str, Any] = {
        "format": FORMAT_VERSION, "old": old_label, "new": new_label, "equal": not changes,
        "summary": {name: sum(1 for c in changes if c.change == name) for name in _ORDER},
        "changes": [_change_json(c) for c in changes],
    }
    if affected is not None:
        document["affected"] = {"out_dir": affected.out_dir, "target": affected.target,
                                "files": [{"action": a.action, "path": a.path} for a in affected.files]}
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"


def _change_json(change: Change) -> dict[str, Any]:
    return {"change": change.change, "kind": change.kind, "path": change.path, "old_path": change.old_path,
            "xmi_id": change.xmi_id, "where": change.where, "instances": change.instances,
            "fields": [{"field": f.field, "old": f.old, "new": f.new} for f in change.fields],
            "contents": dict(change.contents)}

"""The verification result as text, JSON, SARIF 2.1.0 (with codeFlows) or GitHub annotations."""

from __future__ import annotations

import json
from typing import Any

from earl_m2t.verify.run import Finding, TraceStep, VerifyResult

FORMAT_VERSION = 1


def _values(step: TraceStep) -> str:
    return ", ".join(f"{label}={'true' if value else 'false'}" for label, value in step.values)


def trace_lines(trace: tuple[TraceStep, ...]) -> list[str]:
    lines = []
    for step in trace:
        why = f" by {step.why}" if step.source != step.target or "," in step.why else f" ({step.why})"
        values = f"  [{_values(step)}]" if step.values else ""
        lines.append(f"  {step.number}. {step.subsystem}: {step.source} → {step.target}{why}{values}")
    return lines or ["  (in the initial states)"]


def render_text(model_name: str, result: VerifyResult) -> str:
    out = [f"verify {model_name}: {len(result.processes)} subsystem process(es): {', '.join(result.processes) or '-'}"]
    for finding in result.findings:
        out.append(f"{finding.location}: {finding.code} error: {finding.element}: {finding.message}")
        if finding.trace:
            out.append(" counterexample:")
            out.extend(trace_lines(finding.trace))
    for line in result.proven:
        out.append(f"proven: {line}")
    for line in result.not_proven:
        out.append(f"not proven: {line}")
    out.append(f"explored {result.states} states, {result.transitions} transitions, depth {result.depth}")
    return "\n".join(out) + "\n"


def _finding_dict(finding: Finding) -> dict[str, Any]:
    loc = finding.location
    return {
        "code": finding.code, "message": finding.message, "element": finding.element,
        "file": loc.file, "line": loc.line,
        "trace": [{"step": s.number, "subsystem": s.subsystem, "from": s.source, "to": s.target, "by": s.why,
                   "values": dict(s.values)} for s in finding.trace],
    }


def render_json(model_name: str, result: VerifyResult) -> str:
    data = {
        "format_version": FORMAT_VERSION, "model": model_name, "processes": result.processes,
        "left_out": result.left_out, "findings": [_finding_dict(f) for f in result.findings],
        "proven": result.proven, "not_proven": result.not_proven,
        "explored": {"states": result.states, "transitions": result.transitions, "depth": result.depth},
    }
    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"


def render_sarif(model_name: str, result: VerifyResult) -> str:
    results = []
    for finding in result.findings:
        region = {"region": {"startLine": finding.location.line}} if finding.location.line else {}
        loc = {"physicalLocation": {"artifactLocation": {"uri": finding.location.file}, **region}}
        entry: dict[str, Any] = {"ruleId": finding.code, "level": "error",
                                 "message": {"text": f"{finding.element}: {finding.message}"}, "locations": [loc]}
        if finding.trace:
            entry["codeFlows"] = [{"threadFlows": [{"locations": [
                {"location": {**loc, "message": {"text": line.strip()}}} for line in trace_lines(finding.trace)
            ]}]}]
        results.append(entry)
    sarif = {"version": "2.1.0", "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
             "runs": [{"tool": {"driver": {"name": "earl-m2t verify", "rules": [
                 {"id": code} for code in sorted({f.code for f in result.findings})]}},
                       "results": results}]}
    return json.dumps(sarif, indent=2, ensure_ascii=False) + "\n"


def render_github(model_name: str, result: VerifyResult) -> str:
    out = []
    for finding in result.findings:
        where = f"file={finding.location.file}" + (f",line={finding.location.line}" if finding.location.line else "")
        steps = "%0A".join(line.strip() for line in trace_lines(finding.trace)) if finding.trace else ""
        out.append(f"::error {where},title={finding.code}::{finding.element}: {finding.message}"
                   + (f"%0A{steps}" if steps else ""))
    for line in result.not_proven:
        out.append(f"::warning title=not proven::{line}")
    return "".join(line + "\n" for line in out)


RENDERERS = {"text": render_text, "json": render_json, "sarif": render_sarif, "github": render_github}

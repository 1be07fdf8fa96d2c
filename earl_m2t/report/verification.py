"""The report's section on ``earl-m2t verify``: what was proven, and each finding with its
counterexample drawn as a sequence diagram (:mod:`earl_m2t.verify.sequence`, rendered by ``dot``)."""

from __future__ import annotations

from earl_m2t.gen.dot import run_dot
from earl_m2t.gen.views.tables import SpecTables
from earl_m2t.model.elements import EarlModel
from earl_m2t.verify.run import VerifyResult
from earl_m2t.verify.sequence import counterexample_dot


def verification_view(model: EarlModel, result: VerifyResult, folder: str, files: dict[str, bytes],
                      tables: SpecTables) -> dict[str, object]:
    """The report's view of a verification; writes a sequence diagram per counterexample into ``files``."""
    rows = []
    for number, finding in enumerate(result.findings, 1):
        diagram = ""
        if finding.trace:
            name = f"{folder}counterexample-{number}"
            source = counterexample_dot(model, finding)
            files[f"{name}.dot"] = bytes(source)
            files[f"{name}.svg"] = run_dot(bytes(source), "svg", name).output
            diagram = f"{name}.svg"
        rows.append({"code": finding.code, "element": finding.element, "message": finding.message,
                     "line": finding.location.line, "diagram": diagram,
                     "anchor": tables.anchors.nearest(finding.element) if finding.element else ""})
    return {"findings": rows, "proven": result.proven, "not_proven": result.not_proven,
            "explored": f"{result.states} states, {result.transitions} transitions, depth {result.depth}"}

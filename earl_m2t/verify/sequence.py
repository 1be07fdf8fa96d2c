"""A counterexample as a Graphviz sequence diagram (transforms/report/templates/counterexample.dot.j2)."""

from __future__ import annotations

from earl_m2t.gen.diagrams import dot_environment
from earl_m2t.gen.engine import load_target, render
from earl_m2t.model.elements import EarlModel
from earl_m2t.verify.run import Finding

TARGET = "diagrams"


def counterexample_dot(model: EarlModel, finding: Finding) -> bytes:
    env = dot_environment()
    involved = list(dict.fromkeys(step.subsystem for step in finding.trace))
    lifelines = []
    for index, path in enumerate(involved):
        lifelines.append({"id": f"l{index}", "name": path, "initial": _initially(model, path)})
    ids = {path: f"l{index}" for index, path in enumerate(involved)}
    steps = [{
        "number": step.number,
        "lifeline": ids[step.subsystem],
        "text": f"{step.source} → {step.target}" + (f" by {step.why}" if "," in step.why else f" ({step.why})"),
        "predicates": ", ".join(f"{label}={'true' if value else 'false'}" for label, value in step.values),
    } for step in finding.trace]
    title = f"{finding.code} {finding.element}: {finding.message}"
    template = str(load_target(TARGET)["verify"]["counterexample"])
    return render(env, template, title=title, lifelines=lifelines, steps=steps)


def _initially(model: EarlModel, path: str) -> str:
    """What a lifeline shows under its name: a subsystem's initial state; an agent or a link (the
    steps of a switch) says which it is (Graphviz rejects an empty line)."""
    sub = model.subsystem(path)
    if sub is not None:
        return sub.fsm.initial or "" if sub.fsm is not None else ""
    if any(a.path == path for a in model.agents):
        return "agent"
    return "link" if any(link.path == path for link in model.links) else ""

"""The structural rules per configuration: a rule whose answer depends on which agents and links
are present runs again on the structure each configuration induces, and what it finds there
but not in the general model is reported under its own code, the message prefixed with the
configurations it holds in (``[configuration useB]``). Models without configurations are not
touched.

S001 and S002 (a robot left without agents), S006 (an agent left without effectors, receptors
and inter-agent links) and the chains C004 and C005 (links inside an agent may vary) are run.
S003–S005, S008 and S009 are about an agent's own subsystems and buffers, which a configuration
does not change; S007 compares the declared type with the type of the general model, which
counts every link the agent may have. Link-local rules (C001–C003, C006, C008) run once on the
general model, so a link is valid in every configuration that holds it.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from earl_m2t.analysis.switching import induced_model
from earl_m2t.check.rule import Finding
from earl_m2t.model.elements import EarlModel

PER_CONFIGURATION = frozenset({"S001", "S002", "S006", "C004", "C005"})


def per_configuration(model: EarlModel, general: Iterable[Finding],
                      run: Callable[[EarlModel], Iterable[Finding]]) -> list[Finding]:
    """What ``run`` finds on some configuration's structure and not on the general model, one
    finding per element and message, naming the configurations it holds in."""
    known = {(f.element, f.message) for f in general}
    found: dict[tuple[str, str], tuple[Finding, list[str]]] = {}
    for system in model.systems:
        for cfg in system.configurations:
            for finding in run(induced_model(model, system, cfg)):
                key = (finding.element, finding.message)
                if key not in known:
                    found.setdefault(key, (finding, []))[1].append(cfg.name)
    return [Finding(f"[{'configuration' if len(names) == 1 else 'configurations'} {', '.join(names)}] "
                    f"{finding.message}", finding.location, finding.element)
            for finding, names in found.values()]

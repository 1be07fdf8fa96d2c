"""C rules: communication links between subsystems and agents (paper Sec. 2.3, Fig. 7)."""

from __future__ import annotations

from collections.abc import Iterator

from earl_m2t.check.rule import Finding, rule
from earl_m2t.check.tables import permitted_links
from earl_m2t.model.elements import Buffer, EarlModel, Link
from earl_m2t.model.graph import subsystem_graph
from earl_m2t.model.kinds import ReceiveMode, Reliability
from earl_m2t.model.typecompare import structural_difference


def _kinds(model: EarlModel, link: Link) -> tuple[str, str] | None:
    source = model.subsystem_of(link.source)
    target = model.subsystem_of(link.target)
    if source is None or target is None:
        return None
    return source.kind, target.kind


@rule("C001")
def link_not_output_to_input(model: EarlModel) -> Iterator[Finding]:
    for link in model.links:
        if not link.source or not link.target:
            kinds = [model.buffer(end) for end in link.ends]
            directions = " and ".join(
                ("an Output Buffer" if b.direction == "out" else "an Input Buffer") if b else "no buffer" for b in kinds
            )
            yield Finding(f"link {link.path} connects {directions}; a link goes from an Output Buffer to an "
                          "Input Buffer", link.location, link.path)


@rule("C002")
def link_kinds_not_permitted(model: EarlModel) -> Iterator[Finding]:
    table = permitted_links()
    for link in model.links:
        kinds = _kinds(model, link)
        if kinds is None:
            continue
        source = model.subsystem_of(link.source)
        target = model.subsystem_of(link.target)
        assert source is not None and target is not None
        scope = "inter_agent" if source.agent != target.agent else "inter_subsystem"
        if kinds not in table[scope]:
            what = "between agents" if scope == "inter_agent" else "inside an agent"
            yield Finding(f"link {link.path} goes {kinds[0]} → {kinds[1]} {what}, which EARL does not permit",
                          link.location, link.path)


@rule("C003")
def inter_agent_link_not_cs_to_cs(model: EarlModel) -> Iterator[Finding]:
    for link in model.links:
        if link.scope != "system":
            continue
        source = model.subsystem_of(link.source)
        target = model.subsystem_of(link.target)
        if source is None or target is None:
            continue
        if source.agent == target.agent:
            yield Finding(f"inter-agent link {link.path} stays inside agent {source.agent}", link.location, link.path)
        elif source.kind != "cs" or target.kind != "cs":
            yield Finding(f"inter-agent link {link.path} joins {source.path} and {target.path}; only control "
                          "subsystems talk to other agents", link.location, link.path)


def _has_chain(graph, start: str, agent: str, via: str, forward: bool) -> bool:
    """Is there ``start → via → cs`` (forward) or ``cs → via → start`` (backward) inside one agent?"""
    neighbours = graph.successors if forward else graph.predecessors
    return any(
        graph.nodes[middle]["kind"] == via and graph.nodes[middle]["agent"] == agent
        and any(graph.nodes[end]["kind"] == "cs" for end in neighbours(middle))
        for middle in neighbours(start)
    )


@rule("C004")
def real_effector_unreached(model: EarlModel) -> Iterator[Finding]:
    graph = subsystem_graph(model)
    for agent in model.agents:
        for re in agent.re:
            if not _has_chain(graph, re.path, agent.path, "ve", forward=False):
                yield Finding(f"real effector {re.path} is not reached by a chain cs → ve → re", re.location, re.path)


@rule("C005")
def real_receptor_unheard(model: EarlModel) -> Iterator[Finding]:
    graph = subsystem_graph(model)
    for agent in model.agents:
        for rr in agent.rr:
            if not _has_chain(graph, rr.path, agent.path, "vr", forward=True):
                yield Finding(f"real receptor {rr.path} does not reach the control subsystem by a chain "
                              "rr → vr → cs", rr.location, rr.path)


@rule("C006")
def link_datatype_mismatch(model: EarlModel) -> Iterator[Finding]:
    for link in model.links:
        source, target = model.buffer(link.source), model.buffer(link.target)
        if source is None or target is None or not source.datatype or not target.datatype:
            continue
        difference = structural_difference(model.datatypes, source.datatype, target.datatype)
        if difference:
            yield Finding(f"link {link.path} sends {source.datatype} into {target.datatype}: {difference}",
                          link.location, link.path)


@rule("C007")
def input_buffer_unfed(model: EarlModel) -> Iterator[Finding]:
    fed = {link.target for link in model.links if link.target} | {
        end for link in model.links for end in link.ends if end and not link.target
    }
    for sub in model.subsystems:
        for buf in sub.inputs:
            if buf.path not in fed:
                yield Finding(f"input buffer {buf.path} is fed by no link", buf.location, buf.path)


@rule("C008")
def link_name_convention(model: EarlModel) -> Iterator[Finding]:
    for link in model.links:
        source = model.subsystem_of(link.source)
        target = model.subsystem_of(link.target)
        if source is None or target is None:
            continue
        if link.scope == "system":
            expected = f"{source.agent},{target.agent}"
        else:
            expected = f"{source.name},{target.name}"
        if link.name.replace(" ", "") != expected:
            shown = f"is named '{link.name}'" if link.name else "has no name"
            yield Finding(f"the link {link.source} → {link.target} {shown}; by convention it is named "
                          f"'{expected}'", link.location, link.path)


def _qos_problem(source: Buffer, target: Buffer) -> str:
    """Why a link from ``source`` to ``target`` cannot be served as its reliabilities ask: a
    queued input loses no value silently, and DDS never matches a reliable reader with a
    best-effort writer (a reliable writer serves a best-effort reader); "" when it can."""
    dropping = [end for end, buffer in (("the Input Buffer", target), ("the Output Buffer", source))
                if buffer.reliability == Reliability.BEST_EFFORT]
    if target.receive == ReceiveMode.QUEUE and dropping:
        which = "both are" if len(dropping) == 2 else f"{dropping[0]} is"
        return (f"the Input Buffer receives a queue, which loses no value silently, but {which} best_effort; "
                f"make {'them' if len(dropping) == 2 else 'it'} reliable (tag reliability)")
    if source.reliability == Reliability.BEST_EFFORT and target.reliability == Reliability.RELIABLE:
        return ("the Output Buffer is best_effort but the Input Buffer is reliable, a pair DDS never matches, so the "
                "link would carry nothing; make the Output Buffer reliable or the Input Buffer best_effort (tag "
                "reliability)")
    return ""


@rule("C010")
def link_qos_incompatible(model: EarlModel) -> Iterator[Finding]:
    linked = set()
    for link in model.links:
        source, target = model.buffer(link.source), model.buffer(link.target)
        if source is None or target is None:
            continue
        linked.add(target.path)
        problem = _qos_problem(source, target)
        if problem:
            yield Finding(f"link {link.path} ({source.path} → {target.path}): {problem}", link.location, link.path)
    for sub in model.subsystems:
        for buffer in sub.inputs:
            if buffer.path not in linked and buffer.receive == ReceiveMode.QUEUE \
                    and buffer.reliability == Reliability.BEST_EFFORT:
                yield Finding(f"Input Buffer {buffer.path} receives a queue, which loses no value silently, but is "
                              "best_effort; make it reliable (tag reliability)", buffer.location, buffer.path)

"""networkx views of the EARL model for the graph questions: link chains, FSM reachability,
dataType containment."""

from __future__ import annotations

from typing import TYPE_CHECKING

from earl_m2t.model.elements import EarlModel, Fsm

if TYPE_CHECKING:
    import networkx as nx


def subsystem_graph(model: EarlModel) -> nx.DiGraph:
    """Subsystems as nodes (attributes ``kind``, ``agent``), one edge per linked pair, source → target."""
    import networkx as nx

    graph: nx.DiGraph = nx.DiGraph()
    for sub in model.subsystems:
        graph.add_node(sub.path, kind=sub.kind, agent=sub.agent)
    for link in model.links:
        source = model.subsystem_of(link.source)
        target = model.subsystem_of(link.target)
        if source is not None and target is not None:
            graph.add_edge(source.path, target.path)
    return graph


def fsm_graph(fsm: Fsm) -> nx.DiGraph:
    """States as nodes, transitions between states of this FSM as edges."""
    import networkx as nx

    graph: nx.DiGraph = nx.DiGraph()
    graph.add_nodes_from(state.name for state in fsm.states)
    for tr in fsm.transitions:
        if not tr.source_foreign and not tr.target_foreign:
            graph.add_edge(tr.source, tr.target)
    return graph


def unreachable_states(fsm: Fsm) -> list[str]:
    """States no path of transitions reaches from the initial state (empty without one)."""
    initial = fsm.initial
    if not initial:
        return []
    import networkx as nx

    graph = fsm_graph(fsm)
    reached = nx.descendants(graph, initial) | {initial}
    return [state.name for state in fsm.states if state.name not in reached]


def datatype_graph(model: EarlModel) -> nx.DiGraph:
    """dataTypes as nodes, an edge for every field typed by another dataType."""
    import networkx as nx

    graph: nx.DiGraph = nx.DiGraph()
    for key, datatype in model.datatypes.items():
        graph.add_node(key)
        for field in datatype.fields:
            if field.type:
                graph.add_edge(key, field.type, field=field.name)
    return graph

"""Compare two model trees: match elements, report what was added, removed, renamed or changed.

Elements are matched inside their owner by class and key (the element path relative to the
owner); what stays unmatched is paired by XMI id, which makes a renamed element a rename
instead of a removal and an addition. A renamed owner keeps its children matched, since
their keys are relative to it.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace

from earl_m2t.element_tree.nodes import Node
from earl_m2t.element_tree.presentation import presentation


@dataclass(frozen=True)
class FieldChange:
    field: str
    old: str
    new: str


@dataclass(frozen=True)
class Change:
    change: str  # "added" | "removed" | "renamed" | "changed"
    kind: str
    path: str  # in the new model (the old one for a removed element)
    old_path: str  # in the old model ("" for an added element)
    xmi_id: str
    where: str  # file:line in the new model (the old one for a removed element)
    fields: tuple[FieldChange, ...] = ()  # changed fields; for an added or removed element, its details
    contents: tuple[tuple[str, int], ...] = ()  # (kind, count) of what an added/removed element holds
    template_path: str = ""  # see Node.template_path
    old_template_path: str = ""
    instances: int = 1  # how many instances of a replicated element change alike (see collapse_replicas)


def compare(old: Node, new: Node) -> list[Change]:
    """Every change, in the new model's order; removed elements after their former siblings.
    The instances of a replicated element that change alike are one change (their template)."""
    changes: list[Change] = []
    _compare_pair(old, new, changes)
    return collapse_replicas(changes)


def collapse_replicas(changes: list[Change]) -> list[Change]:
    """Changes that differ only in which instance of a replicated element they concern (a
    change of a replicated block shows in each of its instances) as one, named by the
    template path (``manip/a.motorControllerK/ve.fsm.regulate``) with the instance count."""
    groups: dict[tuple[object, ...], list[Change]] = {}
    for change in changes:
        groups.setdefault(_replica_key(change), []).append(change)
    result: list[Change] = []
    for change in changes:
        group = groups[_replica_key(change)]
        if len(group) == 1:
            result.append(change)
        elif group[0] is change:
            old_path = change.old_template_path if change.old_path else ""
            result.append(replace(change, path=change.template_path, old_path=old_path, instances=len(group)))
    return result


def _replica_key(change: Change) -> tuple[object, ...]:
    replicated = change.path != change.template_path
    return (change.change, change.kind, change.template_path, change.old_template_path, change.fields,
            change.contents, replicated)


def _compare_pair(old: Node, new: Node, changes: list[Change]) -> None:
    fields = _field_changes(old, new)
    renamed = old.path != new.path and old.key != new.key
    if renamed or fields:
        changes.append(Change("renamed" if renamed else "changed", new.kind, new.path, old.path, new.xmi_id,
                              str(new.location), tuple(fields), template_path=new.template_path,
                              old_template_path=old.template_path))
    pairs, added, removed = _match(old.children, new.children)
    matched_new = {id(n): o for o, n in pairs}
    added_ids = {id(n) for n in added}
    for child in new.children:
        if id(child) in matched_new:
            _compare_pair(matched_new[id(child)], child, changes)
        elif id(child) in added_ids:
            changes.append(_whole("added", child))
    changes.extend(_whole("removed", child) for child in removed)


def _whole(change: str, node: Node) -> Change:
    values = node.value_map
    details = tuple(FieldChange(name, values[name] if change == "removed" else "",
                                values[name] if change == "added" else "")
                    for name in presentation().details.get(node.cls, ()) if values.get(name))
    return Change(change, node.kind, node.path, node.path if change == "removed" else "", node.xmi_id,
                  str(node.location), details, _contents(node), node.template_path,
                  node.template_path if change == "removed" else "")


def _contents(node: Node) -> tuple[tuple[str, int], ...]:
    counts: Counter[str] = Counter()

    def count(n: Node) -> None:
        for child in n.children:
            counts[child.kind] += 1
            count(child)

    count(node)
    return tuple(counts.items())


def _field_changes(old: Node, new: Node) -> list[FieldChange]:
    before, after = old.value_map, new.value_map
    names = list(dict.fromkeys([*before, *after]))
    return [FieldChange(name, before.get(name, ""), after.get(name, ""))
            for name in names if before.get(name, "") != after.get(name, "")]


def _match(old: tuple[Node, ...], new: tuple[Node, ...]) -> tuple[list[tuple[Node, Node]], list[Node], list[Node]]:
    """(matched pairs, added, removed): by class and key, then by class and XMI id."""
    by_key: dict[tuple[str, str], list[Node]] = {}
    for node in old:
        by_key.setdefault((node.cls, node.key), []).append(node)
    pairs: list[tuple[Node, Node]] = []
    unmatched_new: list[Node] = []
    for node in new:
        candidates = by_key.get((node.cls, node.key))
        if candidates:
            pairs.append((candidates.pop(0), node))
        else:
            unmatched_new.append(node)
    position = {id(node): n for n, node in enumerate(old)}
    unmatched_old = sorted((node for nodes in by_key.values() for node in nodes), key=lambda n: position[id(n)])
    by_id: dict[tuple[str, str], list[Node]] = {}
    for node in unmatched_old:
        if node.xmi_id:
            by_id.setdefault((node.cls, node.xmi_id), []).append(node)
    added: list[Node] = []
    for node in unmatched_new:
        candidates = by_id.get((node.cls, node.xmi_id)) if node.xmi_id else None
        if candidates:
            previous = candidates.pop(0)
            unmatched_old.remove(previous)
            pairs.append((previous, node))
        else:
            added.append(node)
    return pairs, added, unmatched_old

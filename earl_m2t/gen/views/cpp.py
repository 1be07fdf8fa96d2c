"""The view of the C++ target: everything ``transforms/cpp/templates`` print, decided here.

Names are made C++ identifiers by :mod:`earl_m2t.gen.names` (one :class:`Scope` per C++
scope, in model order, so output is deterministic); conditions are compiled from their
parsed expressions by :mod:`earl_m2t.gen.cpp_expr`. Templates receive dicts and lists only.
"""

from __future__ import annotations

import math

from dataclasses import dataclass, field
from typing import Any

from earl_m2t.gen.cpp_expr import ExprCompiler, Storage, Symbols
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import Scope, cpp_comment, cpp_identifier, cpp_string
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import Activation, Buffer, EarlModel, Memory, Subsystem
from earl_m2t.model.naming import stem
from earl_m2t.predicate import Expr, FieldRef, NewData, PredicateRef, walk

Data = dict[str, Any]

# names the generated classes define themselves, per scope
_SUBSYSTEM_RESERVED = ("Data", "Subsystem", "data", "data_", "tables", "execute", "fun",
                       "startHook", "updateHook", "stopHook", "name", "period", "setPeriod",
                       "setObserver", "observer", "iteration", "steps", "currentState",
                       "currentStateName", "Base")
_AGENT_RESERVED = ("Agent", "step", "components", "setObserver", "kComponents")
_MODEL_RESERVED = ("types", "System", "system")  # "system": the system executable and its main


@dataclass(frozen=True)
class CppTarget:
    """The data of ``transforms/cpp/target.toml`` the view needs."""

    types: dict[str, str]
    string_capacity: int
    unbounded_capacity: int
    cycles: int
    period_ms: int


@dataclass
class CppView:
    """Everything the templates need: ``system``, ``agents``, ``subsystems``, user files."""

    system: Data
    agents: list[Data] = field(default_factory=list)
    subsystems: list[Data] = field(default_factory=list)
    user_pf: list[Data] = field(default_factory=list)
    user_pp: list[Data] = field(default_factory=list)


def build_view(model: EarlModel, target: CppTarget) -> CppView:
    """The view of a model; raises GenError when it cannot be generated."""
    if model.system is None:
        raise GenError("the model has no EARL System to generate")
    return _Builder(model, target).build()


class _Builder:
    def __init__(self, model: EarlModel, target: CppTarget) -> None:
        self.model = model
        self.target = target
        self.ns = cpp_identifier(model.name or (model.system.name if model.system else "model"))
        self.type_names: dict[str, str] = {}  # datatype key -> C++ type
        self.field_names: dict[tuple[str, str], str] = {}
        self.defs: dict[str, Data] = {}  # subsystem instance path -> its member in the agent
        self.definitions: dict[str, Data] = {}  # block id -> subsystem definition view
        self.port_members: dict[str, dict[str, str]] = {}  # block id -> buffer template -> port member

    # ------------------------------------------------------------------ dataTypes

    def datatypes(self) -> list[Data]:
        scope = Scope(_MODEL_RESERVED)
        user = [key for key in sorted(self.model.datatypes) if self.model.datatypes[key].kind != "primitive"]
        for key in user:
            self.type_names[key] = f"::{self.ns}::types::{scope.take(self.model.datatypes[key].name)}"
        ordered: list[str] = []
        visiting: set[str] = set()

        def visit(key: str) -> None:
            if key in ordered or key not in user:
                return
            if key in visiting:
                raise GenError(f"dataType {key} contains itself by value")
            visiting.add(key)
            for f in self.model.datatypes[key].fields:
                visit(f.type)
            visiting.discard(key)
            ordered.append(key)

        for key in user:
            visit(key)
        result: list[Data] = []
        for key in ordered:
            datatype = self.model.datatypes[key]
            name = self.type_names[key].rpartition("::")[2]
            fields_scope = Scope((name,))
            if datatype.kind == "enumeration":
                result.append({"kind": "enum", "name": name, "key": key, "comment": cpp_comment(key), "trace": key,
                               "literals": [fields_scope.take(lit) for lit in datatype.literals]})
                continue
            fields = []
            for f in datatype.fields:
                member = fields_scope.take(f.name)
                self.field_names[(key, f.name)] = member
                fields.append({"name": member, "trace": f"{key}.{f.name}",
                               "type": self._field_type(f.type, f.lower, f.upper, key, f.name),
                               "comment": cpp_comment(f"{f.name}: {f.type or f.type_ref}"
                                                      f"{_multiplicity(f.lower, f.upper)}")})
            result.append({"kind": "struct", "name": name, "key": key, "comment": cpp_comment(key), "fields": fields,
                           "trace": key})
        return result

    def cpp_type(self, key: str, where: str) -> str:
        datatype = self.model.datatypes.get(key)
        if datatype is None:
            raise GenError(f"{where}: no dataType (rules S009, D001)")
        if datatype.kind == "primitive":
            mapped = self.target.types.get(datatype.primitive)
            if mapped is None:
                raise GenError(f"{where}: primitive '{datatype.name}' has no C++ type in target.toml")
            return mapped.format(capacity=self.target.string_capacity)
        return self.type_names[key]

    def _field_type(self, key: str, lower: int, upper: int | None, owner: str, name: str) -> str:
        base = self.cpp_type(key, f"field {owner}.{name}")
        if upper is not None and upper > 1 and lower == upper:
            return f"std::array<{base}, {upper}>"
        if upper is None:
            return f"earl::BoundedArray<{base}, {self.target.unbounded_capacity}>"
        if upper != 1 or lower != 1:
            return f"earl::BoundedArray<{base}, {max(upper, 1)}>"
        return base

    # ------------------------------------------------------------------ structure

    def build(self) -> CppView:
        types = self.datatypes()
        system = self.model.system
        assert system is not None
        fan = self._link_counts()
        agents_scope = Scope(_MODEL_RESERVED + (self.ns,))
        agent_ns: dict[str, str] = {a.path: agents_scope.take(a.name) for a in system.agents}
        view = CppView(system={})
        # subsystem definitions, placed under the agent of their first instance
        sub_scopes = {a.path: Scope(_AGENT_RESERVED) for a in system.agents}
        owner_agent = {sub.path: a.path for a in system.agents for sub in a.subsystems}
        for definition in self.model.definitions():
            agent_path = owner_agent[definition.path]
            sub_ns = sub_scopes[agent_path].take(definition.template or definition.name)
            view.subsystems.append(self._subsystem(definition, agent_ns[agent_path], sub_ns, fan, view))
        self.port_members = {d["block_id"]: d["port_members"] for d in view.subsystems}
        self.definitions = {d["block_id"]: d for d in view.subsystems}
        for agent in system.agents:
            view.agents.append(self._agent(agent.path, agent_ns[agent.path]))
        members = Scope(("System", "step", "components", "setObserver", "kComponents"))
        agents: list[Data] = [{"member": members.take(a.name), "cls": f"::{self.ns}::{agent_ns[a.path]}::Agent",
                   "ns": agent_ns[a.path], "path": a.path, "trace": a.path,
                   "components": len(a.subsystems)} for a in system.agents]
        by_path = {a["path"]: a for a in agents}
        links = []
        for link in system.links:
            links.append(self._link(link, members, lambda p: by_path[self._agent_of(p)]["member"] + "."))
        executables: list[Data] = [{"name": f"{self.ns}_system", "source": "generated/src/system_main.cpp"}]
        executables += [{"name": f"{self.ns}_{a['ns']}", "source": f"generated/src/{a['ns']}_main.cpp"}
                        for a in agents]
        view.system = {
            "trace": system.path, "ns": self.ns, "model": cpp_comment(self.model.name), "name": cpp_string(system.name),
            "types": types, "agents": agents, "links": links,
            "components": sum(a["components"] for a in agents),
            "includes": [f"{self.ns}/{a['ns']}/agent.hpp" for a in agents],
            "main": {"include": f"{self.ns}/system.hpp", "cls": f"::{self.ns}::System",
                     "what": cpp_comment(f"system {system.name}"), "name": cpp_string(system.name),
                     "cycles": self.target.cycles, "period_ms": self.target.period_ms},
            "executables": executables,
        }
        return view

    def _agent_of(self, buffer_path: str) -> str:
        sub = self.model.subsystem_of(buffer_path)
        if sub is None:
            raise GenError(f"link end {buffer_path} is not a buffer of a subsystem")
        return sub.agent

    def _link_counts(self) -> dict[tuple[str, str], int]:
        """(block id, buffer template) -> the most links any instance of that buffer has."""
        per_buffer: dict[str, int] = {}
        for link in self.model.links:
            for end in (link.source, link.target):
                if end:
                    per_buffer[end] = per_buffer.get(end, 0) + 1
        counts: dict[tuple[str, str], int] = {}
        for sub in self.model.subsystems:
            for buf in sub.buffers:
                key = (sub.block_id, buf.template)
                counts[key] = max(counts.get(key, 1), per_buffer.get(buf.path, 0))
        return counts

    # ------------------------------------------------------------------ one subsystem definition

    def _subsystem(self, sub: Subsystem, agent_ns: str, sub_ns: str, fan: dict[tuple[str, str], int],
                   view: CppView) -> Data:
        where = sub.path
        scope = Scope(_SUBSYSTEM_RESERVED)
        namespace = f"{self.ns}::{agent_ns}::{sub_ns}"
        storage: dict[str, Storage] = {}
        ports: dict[str, Data] = {}  # buffer template -> port data
        for buf in sub.buffers:
            if buf.template in ports:
                ports[buf.template]["count"] += 1
                continue
            member = scope.take(buf.template, "_newData", "_count")
            ports[buf.template] = {
                "trace": buf.path,
                "member": member, "direction": buf.direction, "kind": "ib" if buf.direction == "in" else "ob",
                "type": self.cpp_type(buf.datatype, buf.path), "replicated": bool(buf.index), "count": 1,
                "links": fan.get((sub.block_id, buf.template), 1), "comment": cpp_comment(buf.template),
                "queue": buf.queue_size if buf.direction == "in" and buf.receive == "queue" else 0,
                "name": cpp_string(buf.template),
            }
        for buf in sub.buffers:
            port = ports[buf.template]
            cpp = f"data_.{port['member']}" + (f"[{buf.index - 1}]" if buf.index else "")
            storage[buf.name] = Storage(cpp, buf.datatype, port["kind"])
        memories: dict[str, Data] = {}
        for mem in sub.memory:
            descriptive = stem(mem.template)
            if descriptive in memories:
                memories[descriptive]["count"] += 1
                continue
            base = scope.take(descriptive, "_m", "_mi", "_mo", "_count")
            memories[descriptive] = {"trace": mem.path, "member": f"{base}_m", "read": f"{base}_mi", "write": f"{base}_mo",
                              "count_name": f"{base}_count",
                              "type": self.cpp_type(mem.datatype, mem.path), "replicated": bool(mem.index),
                              "count": 1, "comment": cpp_comment(mem.template)}
        for mem in sub.memory:
            data = memories[stem(mem.template)]
            storage[f"m:{stem(mem.name)}"] = Storage(
                f"data_.{data['member']}" + (f"[{mem.index - 1}]" if mem.index else ""), mem.datatype, "m")
        for port in ports.values():
            port["count_name"] = f"{port['member']}_count"
            queue = f", {port['queue']}" if port["queue"] else ""
            port["cpp_type"] = (f"earl::{'InputPort' if port['kind'] == 'ib' else 'OutputPort'}"
                                f"<{port['type']}, {port['links']}{queue}>")
            if port["replicated"]:
                port["cpp_type"] = f"std::array<{port['cpp_type']}, {port['count']}>"
        for entry_m in memories.values():
            entry_m["cpp_type"] = (f"std::array<{entry_m['type']}, {entry_m['count']}>" if entry_m["replicated"]
                                   else entry_m["type"])

        user_dir = f"{agent_ns}/{sub_ns}"
        predicates: list[Data] = []
        calls: dict[str, str] = {}
        pp_ids: dict[str, str] = {}
        for pp in sub.predicates:
            pp_ids[pp.name] = scope.take(pp.name, "_base", "_")
            calls[pp.name] = f"{pp_ids[pp.name]}()"
        symbols = Symbols(storage, calls, self.field_names, self.target.unbounded_capacity)
        compiler = ExprCompiler(self.model, sub, symbols)
        parsed: dict[str, Expr] = {}  # the expanded condition of each element compiled, by its name in errors

        def compile_condition(condition: Condition | None, default: bool, what: str) -> str:
            if condition is None:
                return "true" if default else "false"
            compiled = compiler.compile(condition, what)
            assert condition.expanded is not None
            parsed[what] = condition.expanded
            return compiled

        for pp in sub.predicates:
            ident = pp_ids[pp.name]
            entry: Data = {"method": ident, "comment": cpp_comment(f"{pp.name} = {pp.body}"), "trace": pp.path}
            if pp.fun is not None:
                entry.update(user=False, expr=compile_condition(pp.fun, False, pp.path))
            else:
                entry.update(user=True, cls=ident, base=f"{ident}_base", member=f"{ident}_",
                             qualified=f"::{namespace}::{ident}")
                view.user_pp.append({"agent": agent_ns, "sub": sub_ns, "name": ident, "path": pp.path, "trace": pp.path,
                                     "namespace": namespace, "cls": ident, "base": f"{ident}_base",
                                     "include": f"{self.ns}/{user_dir}/data.hpp",
                                     "language": cpp_comment(pp.language),
                                     "body": _body(pp.body)})
            predicates.append(entry)

        functions: list[Data] = []
        pf_ids: dict[str, Data] = {}
        paths = {b.path: b for b in sub.buffers}
        mem_paths = {m.path: m for m in sub.memory}
        for pf in sub.functions:
            ident = scope.take(pf.name, "_base", "_")
            run = scope.take(f"run_{ident}")
            accessors = self._accessors(pf.reads, pf.writes, paths, mem_paths, ports, memories)
            entry = {"cls": ident, "base": f"{ident}_base", "member": f"{ident}_", "run": run, "trace": pf.path,
                     "qualified": f"::{namespace}::{ident}", "accessors": accessors,
                     "comment": cpp_comment(pf.name)}
            functions.append(entry)
            pf_ids[pf.name] = entry
            view.user_pf.append({"agent": agent_ns, "sub": sub_ns, "name": ident, "path": pf.path, "trace": pf.path,
                                 "namespace": namespace, "cls": ident, "base": f"{ident}_base",
                                 "include": f"{self.ns}/{user_dir}/data.hpp", "accessors": accessors,
                                 "language": cpp_comment(pf.language),
                                 "body": _body(pf.body)})
        pp_base_accessors = self._accessors(tuple(paths) + tuple(mem_paths), (), paths, mem_paths, ports, memories)

        fsm = sub.fsm
        if fsm is None or not fsm.initial or all(s.name != fsm.initial for s in fsm.states):
            raise GenError(f"{where}: the FSM has no single initial state (rule B001)")
        states = list(fsm.states)
        state_index = {s.name: i for i, s in enumerate(states)}
        behaviours: list[Data] = []
        bb_index: dict[str, int] = {}
        for bb in sub.behaviours:
            bb_id = cpp_identifier(bb.name)
            stages = []
            for n, stage in enumerate(bb.stages, start=1):
                unknown = [name for name in stage if name not in pf_ids]
                if unknown:
                    raise GenError(f"{bb.path}: stage {n} names unknown pf {', '.join(unknown)} (rule T005)")
                stages.append({"name": scope.take(f"stage_{bb_id}_{n}"), "runs": [pf_ids[p]["run"] for p in stage]})
            writes = {t for p in bb.functions for t in sub.function(p).writes} if bb.functions else set()  # type: ignore[union-attr]
            reads = {t for p in bb.functions for t in sub.function(p).reads} if bb.functions else set()  # type: ignore[union-attr]
            tc = compile_condition(bb.tc, False, f"{bb.path} tc")
            ec = compile_condition(bb.ec, False, f"{bb.path} ec")
            bb_index[bb.name] = len(behaviours)
            behaviours.append({
                "trace": bb.path, "name": cpp_string(bb.name), "comment": cpp_comment(bb.name),
                "stages": stages, "stages_table": scope.take(f"stages_{bb_id}") if stages else "",
                "send": scope.take(f"send_{bb_id}"), "receive": scope.take(f"receive_{bb_id}"),
                "tc": scope.take(f"tc_{bb_id}"), "ec": scope.take(f"ec_{bb_id}"),
                "tc_expr": tc, "ec_expr": ec,
                "tc_text": cpp_comment(bb.tc.text if bb.tc else "none: never terminates"),
                "ec_text": cpp_comment(bb.ec.text if bb.ec else "none"),
                "sends": _port_list(ports, [paths[p] for p in paths if p in writes and paths[p].direction == "out"]),
                "receive_paths": {p for p in reads if p in paths and paths[p].direction == "in"},
                "conditions": [f"{bb.path} tc", f"{bb.path} ec"],
            })
        state_rows = []
        for state in states:
            if len(state.behaviours) != 1 or state.behaviours[0] not in bb_index:
                raise GenError(f"{state.path}: needs exactly one basic behaviour (rule B002)")
            state_rows.append({"name": cpp_string(state.name), "behaviour": bb_index[state.behaviours[0]],
                               "trace": state.path})
        groups, activations = activation_rows(sub, ports, scope)
        transitions = []
        for tr in sorted(fsm.transitions, key=lambda t: t.order):
            if tr.source not in state_index or tr.target not in state_index:
                raise GenError(f"{tr.path}: source or target is not a state of this FSM (rule B003)")
            guard = scope.take(f"ic_{tr.name}")
            expr = compile_condition(tr.condition, True, tr.path)
            transitions.append({"trace": tr.path, "name": cpp_string(tr.name), "label": cpp_comment(tr.name),
                                "source": state_index[tr.source],
                                "target": state_index[tr.target], "priority": tr.priority, "guard": guard,
                                "expr": expr, "text": cpp_comment(tr.condition.text if tr.condition else "none")})
            behaviours[bb_index[states[state_index[tr.source]].behaviours[0]]]["conditions"].append(tr.path)
        # inputs received by a behaviour: those its pf read, and those its own conditions
        # (tc, ec, and the guards leaving its states) read, so they can see new data
        by_name = {b.name: b for b in sub.buffers}
        for row in behaviours:
            received = set(row.pop("receive_paths"))
            for what in row.pop("conditions"):
                if what in parsed:
                    received |= {by_name[name].path for name in self._inputs_of(parsed[what], sub, parsed)
                                 if name in by_name and by_name[name].direction == "in"}
            row["receives"] = _port_list(ports, [b for b in sub.inputs if b.path in received])

        return {
            "trace": sub.path, "ns": namespace, "agent": agent_ns, "sub": sub_ns, "path": sub.path,
            "comment": cpp_comment(sub.path),
            "block": cpp_comment(sub.block), "includes_types": f"{self.ns}/types.hpp",
            "data_include": f"{self.ns}/{user_dir}/data.hpp",
            "user_includes": [f"{user_dir}/{f['cls']}.hpp" for f in functions]
            + [f"{user_dir}/{p['cls']}.hpp" for p in predicates if p["user"]],
            "ports": list(ports.values()), "memory": list(memories.values()),
            "functions": functions, "predicates": predicates, "pp_accessors": pp_base_accessors,
            "behaviours": behaviours, "states": state_rows, "transitions": transitions,
            "initial": state_index[fsm.initial], "groups": groups, "activations": activations,
            "queued": [p for p in ports.values() if p["queue"]],
            "block_id": sub.block_id, "port_members": {t: p["member"] for t, p in ports.items()},
        }

    def _inputs_of(self, expanded: Expr, sub: Subsystem, parsed: dict[str, Expr],
                   seen: frozenset[str] = frozenset()) -> set[str]:
        """Buffer names an expanded condition reads, through the primitive predicates it calls."""
        assert sub.scope is not None
        names: set[str] = set()
        for node in walk(expanded):
            if isinstance(node, FieldRef):
                names.add(node.head)
            elif isinstance(node, NewData):
                names.add(node.ref.head)
            elif isinstance(node, PredicateRef):
                pp_name = sub.scope.predicate(node.name)
                if pp_name is None:
                    names.add(node.name)
                elif pp_name not in seen:
                    pp = sub.predicate(pp_name)
                    if pp is not None and pp.fun is not None and pp.path in parsed:
                        names |= self._inputs_of(parsed[pp.path], sub, parsed, seen | {pp_name})
                    elif pp is not None and pp.fun is None:
                        names |= {b.name for b in sub.inputs}  # user code may read any input
        return names

    def _accessors(self, reads: tuple[str, ...], writes: tuple[str, ...], paths: dict[str, Buffer],
                   mem_paths: dict[str, Memory], ports: dict[str, Data], memories: dict[str, Data]) -> list[Data]:
        """The protected accessors of a pf (or pp) base: one per buffer or memory it may use."""
        result: list[Data] = []
        seen: set[str] = set()
        for path in [*writes, *reads]:
            writing = path in writes
            if path in paths:
                buf = paths[path]
                port = ports[buf.template]
                key = f"port:{port['member']}"
                if key in seen:
                    continue
                seen.add(key)
                result.append({"kind": port["kind"], "name": port["member"], "member": port["member"],
                               "type": port["type"], "replicated": port["replicated"], "count": port["count"],
                               "count_name": port["count_name"], "mutable": writing and port["kind"] == "ob",
                               "comment": cpp_comment(buf.template)})
            elif path in mem_paths:
                mem = memories[stem(mem_paths[path].template)]
                key = f"mem:{mem['member']}:{writing}"
                if key in seen:
                    continue
                seen.add(key)
                result.append({"kind": "m", "name": mem["write"] if writing else mem["read"],
                               "member": mem["member"], "type": mem["type"], "replicated": mem["replicated"],
                               "count": mem["count"], "count_name": mem["count_name"], "mutable": writing,
                               "comment": cpp_comment(mem_paths[path].template)})
        order = {"ib": 0, "m": 1, "ob": 2}
        return sorted(result, key=lambda a: (order[a["kind"]], a["name"]))

    # ------------------------------------------------------------------ agents and links

    def _agent(self, agent_path: str, agent_ns: str) -> Data:
        agent = next(a for a in self.model.agents if a.path == agent_path)
        members = Scope(_AGENT_RESERVED)
        instances = []
        for sub in agent.subsystems:
            member = members.take(sub.name)
            self.defs[sub.path] = {"member": member}
            definition = self.definitions[sub.block_id]
            instances.append({"member": member, "path": cpp_string(sub.path), "trace": sub.path,
                              "cls": f"::{definition['ns']}::Subsystem",
                              "include": f"{self.ns}/{definition['agent']}/{definition['sub']}/subsystem.hpp"})
        links = [self._link(link, members, lambda _p: "") for link in agent.links]
        includes = list(dict.fromkeys(i["include"] for i in instances))
        return {"trace": agent.path, "ns": agent_ns, "path": agent.path, "comment": cpp_comment(agent.path),
                "instances": instances,
                "subsystems": [{"include": i} for i in includes], "links": links, "model_ns": self.ns,
                "main": {"include": f"{self.ns}/{agent_ns}/agent.hpp", "cls": f"::{self.ns}::{agent_ns}::Agent",
                         "what": cpp_comment(f"agent {agent.path}"), "name": cpp_string(agent.path),
                         "cycles": self.target.cycles, "period_ms": self.target.period_ms}}

    def _link(self, link: Any, scope: Scope, prefix: Any) -> Data:
        if not link.source or not link.target:
            raise GenError(f"{link.path}: a link goes from an Output Buffer to an Input Buffer (rule C001)")
        ends = []
        types = []
        for path in (link.source, link.target):
            sub = self.model.subsystem_of(path)
            buf = self.model.buffer(path)
            if sub is None or buf is None:
                raise GenError(f"{link.path}: end {path} is not a buffer of a subsystem")
            member = self.defs[sub.path]["member"]
            port = self._port_member(sub, buf)
            ends.append(f"{prefix(path)}{member}.data().{port}" + (f"[{buf.index - 1}]" if buf.index else ""))
            types.append(buf.datatype)
        if types[0] != types[1]:
            raise GenError(f"{link.path}: the two ends have different dataTypes (rule C006)")
        target = self.model.buffer(link.target)
        value_type = self.cpp_type(types[0], link.path)
        channel = (f"earl::QueueChannel<{value_type}, {target.queue_size}>"
                   if target is not None and target.receive == "queue" else f"earl::Channel<{value_type}>")
        return {"trace": link.path,
                "member": scope.take(f"link {link.name}"), "type": value_type, "channel": channel,
                "source": ends[0], "target": ends[1], "comment": cpp_comment(link.name)}

    def _port_member(self, sub: Subsystem, buf: Buffer) -> str:
        return self.port_members[sub.block_id][buf.template]


def activation_rows(sub: Subsystem, ports: dict[str, Data], scope: Scope) -> tuple[list[Data], list[Data]]:
    """The readiness check of each buffer group (its obligatory ports) and one ActivationDef row
    per state; ([], []) for a subsystem that runs on its own period in every state."""
    states = sub.fsm.states if sub.fsm is not None else ()
    if not sub.buffer_groups and all(s.activation == Activation() for s in states):
        return [], []
    by_name = {name: b.template for b in sub.inputs for name in (b.name, b.template)}
    groups: dict[str, Data] = {}
    for group in sub.buffer_groups:
        members = [ports[by_name[name]] for name in dict.fromkeys(group.obligatory) if name in by_name]
        if members:
            groups[group.name] = {"method": scope.take(f"obligatory_{group.name}"), "comment": cpp_comment(group.name),
                                  "ports": members}
    rows = []
    for state in states:
        activation = state.activation
        ready = groups.get(activation.group)
        rows.append({"obligatory": f"&Subsystem::{ready['method']}" if ready else "nullptr",
                     "min_period": _nanoseconds(activation.min_period),
                     "first_timeout": _nanoseconds(activation.first_timeout),
                     "next_timeout": _nanoseconds(activation.next_timeout), "comment": cpp_comment(state.name)})
    return list(groups.values()), rows


def _nanoseconds(seconds: float | None) -> int:
    """Seconds as the runtime's nanoseconds; -1 (none) for no value (or one B011 rejects)."""
    if seconds is None or not math.isfinite(seconds) or seconds < 0:
        return -1
    return round(seconds * 1e9)


def _multiplicity(lower: int, upper: int | None) -> str:
    if lower == 1 and upper == 1:
        return ""
    return f"[{lower}..{'*' if upper is None else upper}]"


def _port_list(ports: dict[str, Data], buffers: list[Buffer]) -> list[Data]:
    seen: dict[str, Data] = {}
    for buf in buffers:
        port = ports[buf.template]
        seen.setdefault(port["member"], {"member": port["member"], "replicated": port["replicated"]})
    return list(seen.values())


def _body(text: str) -> list[str]:
    """The body the model gives an element, as comment lines of its user file."""
    lines = [cpp_comment(line).removeprefix("//").strip() for line in text.splitlines()]
    return [line for line in lines if line]

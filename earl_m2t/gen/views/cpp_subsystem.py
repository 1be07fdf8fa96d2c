"""The C++ view of one subsystem definition: its ports and memory, its primitive predicates and
pfs (and their user files), its basic behaviours, states and transitions with their compiled
conditions, and how each state is activated.

The names of one definition share one C++ scope and are taken in model order (ports, memory,
predicates, pfs, behaviours, buffer groups, transitions), so output is deterministic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

from earl_m2t.analysis.receiving import behaviour_inputs
from earl_m2t.gen.cpp_expr import ExprCompiler, Storage, Symbols
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import Scope, cpp_comment, cpp_identifier, cpp_string
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import Activation, BasicBehaviour, Buffer, EarlModel, State, Subsystem
from earl_m2t.model.limits import MAX_SECONDS
from earl_m2t.model.naming import stem

Data = dict[str, Any]

# names the generated subsystem class defines itself
_SUBSYSTEM_RESERVED = ("Data", "Subsystem", "data", "data_", "tables", "execute", "fun",
                       "startHook", "updateHook", "stopHook", "name", "period", "setPeriod",
                       "setObserver", "observer", "iteration", "steps", "currentState",
                       "currentStateName", "Base", "inError", "behaviourOk", "entries", "pfFailed", "written",
                       "nonFinite", "setNonFinite", "fail", "takeFailure", "failure_")
# and those of the base of a subsystem in a model with configurations
_SWITCHING_RESERVED = ("resetData", "quiescent", "leaving", "switching", "joinAgent", "coordinate")


class Types(Protocol):
    """What the model-wide part of the C++ view knows of types."""

    model: EarlModel
    ns: str  # the model's C++ namespace
    field_names: dict[tuple[str, str], str]  # (dataType key, field name) -> C++ member

    @property
    def unbounded_capacity(self) -> int: ...

    def cpp_type(self, key: str, where: str) -> str: ...


@dataclass
class UserFiles:
    """The user files of the definitions: one per pf, one per predicate written in user code."""

    pf: list[Data]
    pp: list[Data]


def subsystem_view(types: Types, sub: Subsystem, agent_ns: str, sub_ns: str, fan: dict[tuple[str, str], int],
                   user: UserFiles, switching: bool = False) -> Data:
    """The view of the definition ``sub``, its user files appended to ``user``; raises GenError.
    ``switching``: the model has configurations (variable structure)."""
    return _SubsystemView(types, sub, agent_ns, sub_ns, fan, user, switching).build()


class _SubsystemView:
    def __init__(self, types: Types, sub: Subsystem, agent_ns: str, sub_ns: str,
                 fan: dict[tuple[str, str], int], user: UserFiles, switching: bool = False) -> None:
        self.types = types
        self.switching = switching
        self.sub = sub
        self.agent_ns = agent_ns
        self.sub_ns = sub_ns
        self.fan = fan
        self.user = user
        self.scope = Scope(_SUBSYSTEM_RESERVED + (_SWITCHING_RESERVED if switching else ()))
        self.namespace = f"{types.ns}::{agent_ns}::{sub_ns}"
        self.user_dir = f"{agent_ns}/{sub_ns}"
        self.storage: dict[str, Storage] = {}
        self.ports: dict[str, Data] = {}  # buffer template -> port data
        self.memories: dict[str, Data] = {}  # memory stem -> memory data
        self.paths = {b.path: b for b in sub.buffers}
        self.mem_paths = {m.path: m for m in sub.memory}
        self.compiler: ExprCompiler | None = None

    def build(self) -> Data:
        sub = self.sub
        self._ports()
        self._memories()
        predicates = self._predicates()
        reason = self.scope.take("pfReason")
        functions, pf_ids = self._functions()
        pp_base_accessors = self._accessors(tuple(self.paths) + tuple(self.mem_paths), ())
        fsm = sub.fsm
        if fsm is None or not fsm.initial or all(s.name != fsm.initial for s in fsm.states):
            raise GenError(f"{sub.path}: the FSM has no single initial state (rule B001)")
        state_index = {s.name: i for i, s in enumerate(fsm.states)}
        behaviours, bb_index = self._behaviours(pf_ids)
        state_rows = []
        for state in fsm.states:
            if len(state.behaviours) != 1 or state.behaviours[0] not in bb_index:
                raise GenError(f"{state.path}: needs exactly one basic behaviour (rule B002)")
            state_rows.append({"name": cpp_string(state.name), "behaviour": bb_index[state.behaviours[0]],
                               "trace": state.path})
        groups, activations = activation_rows(sub, self.ports, self.scope)
        transitions = self._transitions(state_index)
        ns, user_dir = self.types.ns, self.user_dir
        return {
            "trace": sub.path, "ns": self.namespace, "agent": self.agent_ns, "sub": self.sub_ns, "path": sub.path,
            "comment": cpp_comment(sub.path),
            "block": cpp_comment(sub.block), "includes_types": f"{ns}/types.hpp",
            "data_include": f"{ns}/{user_dir}/data.hpp",
            "user_includes": [f"{user_dir}/{f['cls']}.hpp" for f in functions]
            + [f"{user_dir}/{p['cls']}.hpp" for p in predicates if p["user"]],
            "ports": list(self.ports.values()), "memory": list(self.memories.values()),
            "functions": functions, "predicates": predicates, "pp_accessors": pp_base_accessors,
            "behaviours": behaviours, "states": state_rows, "transitions": transitions,
            "initial": state_index[fsm.initial], "groups": groups, "activations": activations,
            "queued": [p for p in self.ports.values() if p["queue"]],
            "block_id": sub.block_id, "port_members": {t: p["member"] for t, p in self.ports.items()},
            "switching": self.switching, "quiescent": _quiescent(fsm.states) if self.switching else [],
            "reason": reason, "held": [p for p in self.ports.values() if p.get("hold")],
        }

    # ------------------------------------------------------------------ data

    def _ports(self) -> None:
        sub, ports, scope = self.sub, self.ports, self.scope
        for buf in sub.buffers:
            if buf.template in ports:
                ports[buf.template]["count"] += 1
                continue
            member = scope.take(buf.template, "_newData", "_count")
            ports[buf.template] = {
                "trace": buf.path,
                "member": member, "direction": buf.direction, "kind": "ib" if buf.direction == "in" else "ob",
                "type": self.types.cpp_type(buf.datatype, buf.path), "replicated": bool(buf.index), "count": 1,
                "links": self.fan.get((sub.block_id, buf.template), 1), "comment": cpp_comment(buf.template),
                "queue": buf.queue_size if buf.direction == "in" and buf.receive == "queue" else 0,
                "name": cpp_string(buf.template),
            }
        for buf in sub.buffers:
            port = ports[buf.template]
            cpp = f"data_.{port['member']}" + (f"[{buf.index - 1}]" if buf.index else "")
            self.storage[buf.name] = Storage(cpp, buf.datatype, port["kind"])
        for index, port in enumerate(p for p in ports.values() if p["kind"] == "ib"):
            port["wake_index"] = index  # earl::Wake::inputBit(wake_index)
        for port in ports.values():
            port["count_name"] = f"{port['member']}_count"
            queue = f", {port['queue']}" if port["queue"] else ""
            inputs = "SwitchedInputPort" if self.switching else "InputPort"
            port["cpp_type"] = (f"earl::{inputs if port['kind'] == 'ib' else 'OutputPort'}"
                                f"<{port['type']}, {port['links']}{queue}>")
            if port["replicated"]:
                port["cpp_type"] = f"std::array<{port['cpp_type']}, {port['count']}>"

    def _memories(self) -> None:
        memories = self.memories
        for mem in self.sub.memory:
            descriptive = stem(mem.template)
            if descriptive in memories:
                memories[descriptive]["count"] += 1
                continue
            base = self.scope.take(descriptive, "_m", "_mi", "_mo", "_count")
            memories[descriptive] = {"trace": mem.path, "member": f"{base}_m", "read": f"{base}_mi",
                                     "write": f"{base}_mo", "count_name": f"{base}_count",
                                     "type": self.types.cpp_type(mem.datatype, mem.path), "replicated": bool(mem.index),
                                     "count": 1, "comment": cpp_comment(mem.template)}
        for mem in self.sub.memory:
            data = memories[stem(mem.template)]
            self.storage[f"m:{stem(mem.name)}"] = Storage(
                f"data_.{data['member']}" + (f"[{mem.index - 1}]" if mem.index else ""), mem.datatype, "m")
        for entry in memories.values():
            entry["cpp_type"] = (f"std::array<{entry['type']}, {entry['count']}>" if entry["replicated"]
                                 else entry["type"])

    # ------------------------------------------------------------------ predicates and pfs

    def _predicates(self) -> list[Data]:
        sub = self.sub
        pp_ids = {pp.name: self.scope.take(pp.name, "_base", "_") for pp in sub.predicates}
        calls = {name: f"{ident}()" for name, ident in pp_ids.items()}
        symbols = Symbols(self.storage, calls, self.types.field_names, self.types.unbounded_capacity)
        self.compiler = ExprCompiler(self.types.model, sub, symbols)
        predicates: list[Data] = []
        for pp in sub.predicates:
            ident = pp_ids[pp.name]
            entry: Data = {"method": ident, "comment": cpp_comment(f"{pp.name} = {pp.body}"), "trace": pp.path}
            if pp.fun is not None:
                entry.update(user=False, expr=self._compile(pp.fun, False, pp.path))
            else:
                entry.update(user=True, cls=ident, base=f"{ident}_base", member=f"{ident}_",
                             qualified=f"::{self.namespace}::{ident}")
                self.user.pp.append(self._user_file(ident, pp.path, pp.language, pp.body))
            predicates.append(entry)
        return predicates

    def _functions(self) -> tuple[list[Data], dict[str, Data]]:
        functions: list[Data] = []
        pf_ids: dict[str, Data] = {}
        for pf in self.sub.functions:
            ident = self.scope.take(pf.name, "_base", "_")
            run = self.scope.take(f"run_{ident}")
            accessors = self._accessors(pf.reads, pf.writes)
            checks = self._checks(ident, pf.writes)
            entry = {"cls": ident, "base": f"{ident}_base", "member": f"{ident}_", "run": run, "trace": pf.path,
                     "qualified": f"::{self.namespace}::{ident}", "accessors": accessors,
                     "comment": cpp_comment(pf.name), "index": len(functions), "name": cpp_string(pf.name),
                     "checks": checks, "check": self.scope.take(f"check_{ident}") if checks else ""}
            functions.append(entry)
            pf_ids[pf.name] = entry
            self.user.pf.append({**self._user_file(ident, pf.path, pf.language, pf.body), "accessors": accessors})
        return functions, pf_ids

    def _checks(self, ident: str, writes: tuple[str, ...]) -> list[Data]:
        """The output buffers a pf writes that hold a real number somewhere: checked for
        non-finite values after it runs, each with its hold flag and its reported flag."""
        checks: list[Data] = []
        for port in _port_list(self.ports, [self.paths[p] for p in writes
                                            if p in self.paths and self.paths[p].direction == "out"]):
            data = next(d for d in self.ports.values() if d["member"] == port["member"])  # the port itself
            if not _holds_real(self.types.model, self.paths[data["trace"]].datatype):
                continue
            if not data.get("hold"):
                data["hold"] = self.scope.take(f"hold_{data['member']}")
            checks.append({"member": data["member"], "replicated": data["replicated"], "count": data["count"],
                           "hold": data["hold"], "flag": self.scope.take(f"nonFinite_{ident}_{data['member']}"),
                           "buffer": data["name"], "comment": data["comment"],
                           "reason": cpp_string(f"a non-finite number in {data['comment']}")})
        return checks

    def _user_file(self, ident: str, path: str, language: str, body: str) -> Data:
        return {"agent": self.agent_ns, "sub": self.sub_ns, "name": ident, "path": path, "trace": path,
                "comment": cpp_comment(path),
                "namespace": self.namespace, "cls": ident, "base": f"{ident}_base",
                "include": f"{self.types.ns}/{self.user_dir}/data.hpp", "language": cpp_comment(language),
                "body": _body(body)}

    def _accessors(self, reads: tuple[str, ...], writes: tuple[str, ...]) -> list[Data]:
        """The protected accessors of a pf (or pp) base: one per buffer or memory it may use."""
        result: list[Data] = []
        seen: set[str] = set()
        for path in [*writes, *reads]:
            writing = path in writes
            if path in self.paths:
                buf = self.paths[path]
                port = self.ports[buf.template]
                key = f"port:{port['member']}"
                if key in seen:
                    continue
                seen.add(key)
                result.append({"kind": port["kind"], "name": port["member"], "member": port["member"],
                               "type": port["type"], "replicated": port["replicated"], "count": port["count"],
                               "count_name": port["count_name"], "mutable": writing and port["kind"] == "ob",
                               "comment": cpp_comment(buf.template)})
            elif path in self.mem_paths:
                mem = self.memories[stem(self.mem_paths[path].template)]
                key = f"mem:{mem['member']}:{writing}"
                if key in seen:
                    continue
                seen.add(key)
                result.append({"kind": "m", "name": mem["write"] if writing else mem["read"],
                               "member": mem["member"], "type": mem["type"], "replicated": mem["replicated"],
                               "count": mem["count"], "count_name": mem["count_name"], "mutable": writing,
                               "comment": cpp_comment(self.mem_paths[path].template)})
        order = {"ib": 0, "m": 1, "ob": 2}
        return sorted(result, key=lambda a: (order[a["kind"]], a["name"]))

    # ------------------------------------------------------------------ behaviour

    def _compile(self, condition: Condition | None, default: bool, what: str) -> str:
        if condition is None:
            return "true" if default else "false"
        assert self.compiler is not None
        return self.compiler.compile(condition, what)

    def _behaviours(self, pf_ids: dict[str, Data]) -> tuple[list[Data], dict[str, int]]:
        behaviours: list[Data] = []
        bb_index: dict[str, int] = {}
        for bb in self.sub.behaviours:
            bb_index[bb.name] = len(behaviours)
            behaviours.append(self._behaviour(bb, pf_ids))
        return behaviours, bb_index

    def _behaviour(self, bb: BasicBehaviour, pf_ids: dict[str, Data]) -> Data:
        sub, scope, paths = self.sub, self.scope, self.paths
        bb_id = cpp_identifier(bb.name)
        stages = []
        for n, stage in enumerate(bb.stages, start=1):
            unknown = [name for name in stage if name not in pf_ids]
            if unknown:
                raise GenError(f"{bb.path}: stage {n} names unknown pf {', '.join(unknown)} (rule T005)")
            stages.append({"name": scope.take(f"stage_{bb_id}_{n}"), "runs": [pf_ids[p]["run"] for p in stage]})
        used = [f for f in (sub.function(p) for p in bb.functions) if f is not None]
        writes = {t for f in used for t in f.writes}
        tc = self._compile(bb.tc, False, f"{bb.path} tc")
        ec = self._compile(bb.ec, False, f"{bb.path} ec")
        return {
            "trace": bb.path, "name": cpp_string(bb.name), "comment": cpp_comment(bb.name),
            "stages": stages, "stages_table": scope.take(f"stages_{bb_id}") if stages else "",
            "send": scope.take(f"send_{bb_id}"), "receive": scope.take(f"receive_{bb_id}"),
            "tc": scope.take(f"tc_{bb_id}"), "ec": scope.take(f"ec_{bb_id}"),
            "tc_expr": tc, "ec_expr": ec,
            "tc_text": cpp_comment(bb.tc.text if bb.tc else "none: never terminates"),
            "ec_text": cpp_comment(bb.ec.text if bb.ec else "none"),
            "sends": _port_list(self.ports, [paths[p] for p in paths if p in writes and paths[p].direction == "out"]),
            "receives": _port_list(self.ports, list(behaviour_inputs(sub, bb))),
        }

    def _transitions(self, state_index: dict[str, int]) -> list[Data]:
        fsm = self.sub.fsm
        assert fsm is not None
        transitions = []
        for tr in sorted(fsm.transitions, key=lambda t: t.order):
            if tr.source not in state_index or tr.target not in state_index:
                raise GenError(f"{tr.path}: source or target is not a state of this FSM (rule B003)")
            guard = self.scope.take(f"ic_{tr.name}")
            expr = self._compile(tr.condition, True, tr.path)
            transitions.append({"trace": tr.path, "name": cpp_string(tr.name), "label": cpp_comment(tr.name),
                                "source": state_index[tr.source],
                                "target": state_index[tr.target], "priority": tr.priority, "guard": guard,
                                "expr": expr, "text": cpp_comment(tr.condition.text if tr.condition else "none")})
        return transitions


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
                     "next_timeout": _nanoseconds(activation.next_timeout),
                     "wake_inputs": _wake_mask(ready["ports"]) if ready else "earl::Wake::kAnyInput",
                     "comment": cpp_comment(state.name)})
    return list(groups.values()), rows


def _input_bit(index: int) -> int:
    """earl::Wake::inputBit(index): the 64th input and later share the last bit."""
    return 1 << min(index, 63)


def _wake_mask(obligatory: list[Data]) -> str:
    """The C++ literal of the bits of a buffer group's obligatory inputs."""
    mask = 0
    for port in obligatory:
        mask |= _input_bit(port["wake_index"])
    return f"0x{mask:x}u"


def _quiescent(states: tuple[State, ...]) -> list[Data]:
    """Per state, whether a switch may stop its agent there; [] when no state is declared
    quiescent (then in any state)."""
    flags = [state.quiescent for state in states]
    if not any(flags):
        return []
    return [{"quiescent": flag, "comment": cpp_comment(state.name)} for flag, state in zip(flags, states)]


def _nanoseconds(seconds: float | None) -> int:
    """Seconds as the runtime's nanoseconds; -1 (none) for no value (or one B011 rejects: gen --force)."""
    if seconds is None or not math.isfinite(seconds) or not 0 <= seconds <= MAX_SECONDS:
        return -1
    return round(seconds * 1e9)


def _port_list(ports: dict[str, Data], buffers: list[Buffer]) -> list[Data]:
    seen: dict[str, Data] = {}
    for buf in buffers:
        port = ports[buf.template]
        seen.setdefault(port["member"], {"member": port["member"], "replicated": port["replicated"],
                                         "count": port["count"], "hold": port.get("hold", "")})
    return list(seen.values())


def _holds_real(model: EarlModel, key: str, seen: frozenset[str] = frozenset()) -> bool:
    """Whether a value of the dataType ``key`` holds a real number anywhere (a NaN can hide there)."""
    datatype = model.datatypes.get(key)
    if datatype is None or key in seen:
        return False
    if datatype.kind == "primitive":
        return datatype.primitive == "real"
    return any(_holds_real(model, f.type, seen | {key}) for f in datatype.fields)


def _body(text: str) -> list[str]:
    """The body the model gives an element, as comment lines of its user file."""
    lines = [cpp_comment(line).removeprefix("//").strip() for line in text.splitlines()]
    return [line for line in lines if line]

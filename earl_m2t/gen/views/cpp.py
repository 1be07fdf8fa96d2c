"""The view of the C++ target: everything ``transforms/cpp/templates`` print, decided here.

Names are made C++ identifiers by :mod:`earl_m2t.gen.names` (one :class:`Scope` per C++
scope, in model order, so output is deterministic); conditions are compiled from their
parsed expressions by :mod:`earl_m2t.gen.cpp_expr`. Templates receive dicts and lists only.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import Scope, cpp_comment, cpp_identifier, cpp_string
from earl_m2t.gen.views.cpp_subsystem import UserFiles, subsystem_view
from earl_m2t.gen.views.cpp_switch import has_configurations, switching_view
from earl_m2t.model import variability
from earl_m2t.model.elements import Buffer, EarlModel, Subsystem
from earl_m2t.model.kinds import SubsystemKind

Data = dict[str, Any]

# names the generated classes define themselves, per scope
_AGENT_RESERVED = ("Agent", "step", "components", "setObserver", "kComponents")
_MODEL_RESERVED = ("types", "System", "system")  # "system": the system executable and its main
# and those a model with configurations adds
_AGENT_SWITCHING = ("joinSlot", "clearLinks")
_SYSTEM_SWITCHING = ("switcher", "switch_", "slots_", "switchLinks_", "kConfigurations", "kAgentMask", "kLinkMask",
                     "kSwitchTimeoutNs", "kStateConfiguration", "kSwitchTables")


@dataclass(frozen=True)
class CppTarget:
    """The data of ``transforms/cpp/target.toml`` the view needs."""

    types: dict[str, str]
    string_capacity: int
    unbounded_capacity: int
    cycles: int
    period_ms: int
    switch_timeout: float = 0.05  # s, for a configuration that sets none


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
        self.switching = has_configurations(model)
        self.agent_reserved = _AGENT_RESERVED + (_AGENT_SWITCHING if self.switching else ())

    @property
    def unbounded_capacity(self) -> int:
        return self.target.unbounded_capacity

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
        sub_scopes = {a.path: Scope(self.agent_reserved) for a in system.agents}
        owner_agent = {sub.path: a.path for a in system.agents for sub in a.subsystems}
        user = UserFiles(view.user_pf, view.user_pp)
        for definition in self.model.definitions():
            agent_path = owner_agent[definition.path]
            sub_ns = sub_scopes[agent_path].take(definition.template or definition.name)
            view.subsystems.append(subsystem_view(self, definition, agent_ns[agent_path], sub_ns, fan, user,
                                                  self.switching))
        self.port_members = {d["block_id"]: d["port_members"] for d in view.subsystems}
        self.definitions = {d["block_id"]: d for d in view.subsystems}
        for agent in system.agents:
            view.agents.append(self._agent(agent.path, agent_ns[agent.path]))
        members = Scope(("System", "step", "components", "setObserver", "kComponents")
                        + (_SYSTEM_SWITCHING if self.switching else ()))
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
        channels = {row["trace"]: row for row in links}
        for agent_row, agent_view in zip(agents, view.agents):
            for row in agent_view["links"]:
                channels[row["trace"]] = {**row, "expression": f"{agent_row['member']}.{row['member']}"}
        switching = switching_view(self.model, agents, channels, {p: d["member"] for p, d in self.defs.items()},
                                   members, self.target.switch_timeout)
        view.system = {
            "trace": system.path, "ns": self.ns, "model": cpp_comment(self.model.name), "name": cpp_string(system.name),
            "types": types, "agents": agents, "links": links, "switching": switching,
            "components": sum(a["components"] for a in agents),
            "includes": [f"{self.ns}/{a['ns']}/agent.hpp" for a in agents],
            "main": {"include": f"{self.ns}/system.hpp", "cls": f"::{self.ns}::System",
                     "what": cpp_comment(f"system {system.name}"), "name": cpp_string(system.name),
                     "cycles": self.target.cycles, "period_ms": self.target.period_ms,
                     "switching": switching is not None},
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

    # ------------------------------------------------------------------ agents and links

    def _agent(self, agent_path: str, agent_ns: str) -> Data:
        agent = next(a for a in self.model.agents if a.path == agent_path)
        members = Scope(self.agent_reserved)
        instances = []
        for sub in agent.subsystems:
            member = members.take(sub.name)
            self.defs[sub.path] = {"member": member}
            definition = self.definitions[sub.block_id]
            instances.append({"member": member, "path": cpp_string(sub.path), "trace": sub.path,
                              "control": sub.kind == SubsystemKind.CS,
                              "cls": f"::{definition['ns']}::Subsystem",
                              "include": f"{self.ns}/{definition['agent']}/{definition['sub']}/subsystem.hpp"})
        links = [self._link(link, members, lambda _p: "") for link in agent.links]
        includes = list(dict.fromkeys(i["include"] for i in instances))
        variable = self.switching and _is_variable(self.model, agent.path)
        control = [sub.path for sub in agent.subsystems if sub.kind == SubsystemKind.CS]
        return {"trace": agent.path, "ns": agent_ns, "path": agent.path, "comment": cpp_comment(agent.path),
                "instances": instances, "switching": self.switching, "variable": variable,
                "control_comment": cpp_comment(control[0] if control else "no control subsystem"),
                "subsystems": [{"include": i} for i in includes], "links": links, "model_ns": self.ns,
                "main": {"include": f"{self.ns}/{agent_ns}/agent.hpp", "cls": f"::{self.ns}::{agent_ns}::Agent",
                         "what": cpp_comment(f"agent {agent.path}"), "name": cpp_string(agent.path),
                         "cycles": self.target.cycles, "period_ms": self.target.period_ms, "switching": False}}

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
        queued = target is not None and target.receive == "queue"
        channel = (f"earl::QueueChannel<{value_type}, {target.queue_size}>" if target is not None and queued
                   else f"earl::Channel<{value_type}>")
        member = scope.take(f"link {link.name}")
        row = {"trace": link.path, "member": member, "type": value_type, "channel": channel,
               "source": ends[0], "target": ends[1], "comment": cpp_comment(link.name)}
        if self.switching:
            receiver = self.model.subsystem_of(link.target)
            row.update(channel=f"earl::VariableLink<{channel}>", queued=queued, name=cpp_string(link.path),
                       expression=member, receiver_subsystem=receiver.path if receiver is not None else "")
        return row

    def _port_member(self, sub: Subsystem, buf: Buffer) -> str:
        return self.port_members[sub.block_id][buf.template]


def _is_variable(model: EarlModel, agent_path: str) -> bool:
    assert model.system is not None
    return agent_path in variability.variable_agents(model.system)


def _multiplicity(lower: int, upper: int | None) -> str:
    if lower == 1 and upper == 1:
        return ""
    return f"[{lower}..{'*' if upper is None else upper}]"

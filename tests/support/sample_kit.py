"""What the sample scripts share: the builder interface of the three tool dialects and small
helpers written against it.

``papyrus_builder``, ``cameo_builder`` and ``ea_builder`` have one API; the protocols below say
the part of it that ``scripts/make_sample.py``, ``scripts/make_two_arm.py`` and
``scripts/make_harmoniser.py`` use, so that a sample's content is written once and saved in
each tool's dialect (:data:`DIALECTS`).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, NamedTuple, Protocol

from tests.support import cameo_builder, ea_builder, papyrus_builder

__all__ = [
    "DIALECTS",
    "Activity",
    "Behavior",
    "Block",
    "DataType",
    "Dialect",
    "ModelBuilder",
    "Package",
    "Property",
    "State",
    "StateMachine",
    "inter_agent_link",
    "link",
    "port",
    "single_state",
    "start_model",
    "write_dialects",
]


# ---- the builder interface the three dialects share ------------------------------------------


class Property(Protocol):
    """A port, part, value property or field."""

    @property
    def name(self) -> str | None: ...

    @property
    def type(self) -> Any: ...

    def stereotype(self, name: str, tags: Mapping[str, Any] | None = ...) -> None: ...


class Behavior(Protocol):
    """A pf or pp."""

    @property
    def name(self) -> str | None: ...


class Activity(Protocol):
    def stages(self, stages: Sequence[Sequence[Any]]) -> Any: ...


class State(Protocol):
    @property
    def name(self) -> str | None: ...

    def do_activity(self, name: str | None = ..., tc: str | None = ..., ec: str | None = ...) -> Activity: ...
    def stereotype(self, name: str, tags: Mapping[str, Any] | None = ...) -> None: ...


class StateMachine(Protocol):
    def state(self, name: str, initial: bool = ...) -> State: ...

    def transition(self, source: Any, target: Any, guard: str | None = ..., name: str | None = ...,
                   priority: int = ...) -> Any: ...  # fmt: skip


class DataType(Protocol):
    def field(self, name: str, type_: Any, multiplicity: Any = ...) -> Property: ...


class Block(Protocol):
    @property
    def attributes(self) -> Sequence[Property]: ...

    def comment(self, body: str) -> Any: ...
    def part(self, name: str, type_: Any, multiplicity: Any = ...) -> Property: ...
    def input_buffer(self, name: str, type_: Any, multiplicity: Any = ...) -> Property: ...
    def output_buffer(self, name: str, type_: Any, multiplicity: Any = ...) -> Property: ...
    def memory(self, name: str, type_: Any, multiplicity: Any = ...) -> Property: ...
    def connector(self, name: str, source: Any, target: Any, stereotype: str | None = ...) -> Any: ...
    def state_machine(self) -> StateMachine: ...
    def primitive_predicate(self, name: str, body: str) -> Behavior: ...
    def exclusion(self, name: str, predicates: Sequence[Any] = ..., body: str | None = ...) -> Any: ...
    def buffer_group(self, name: str, obligatory: Sequence[Property] = ...,
                     optional: Sequence[Property] = ...) -> Any: ...
    def configuration(self, name: str, agents: Sequence[str] = ..., links: Sequence[str] = ...,
                      switch_timeout: float | str | None = ...) -> Any: ...
    def ltl_property(self, name: str, formula: str) -> Any: ...
    def partial_transition_function(self, name: str, reads: Sequence[Any] = ..., writes: Sequence[Any] = ...,
                                    body: str = ...) -> Behavior: ...  # fmt: skip


class Package(Protocol):
    def data_type(self, name: str) -> DataType: ...
    def block(self, name: str, stereotype: str | None = ..., tags: Mapping[str, Any] | None = ...) -> Block: ...


class ModelBuilder(Protocol):
    def package(self, name: str) -> Package: ...
    def comment(self, body: str) -> Any: ...
    def to_bytes(self) -> bytes: ...


class Dialect(NamedTuple):
    """One tool's builder: how to start a model, make a connector end, name the primitive types."""

    name: str
    model_builder: Callable[..., ModelBuilder]
    end_at: Callable[..., Any]
    real: Any
    boolean: Any
    integer: Any


DIALECTS: dict[str, Dialect] = {
    "papyrus": Dialect(
        "papyrus", papyrus_builder.ModelBuilder, papyrus_builder.End.at,
        papyrus_builder.REAL, papyrus_builder.BOOLEAN, papyrus_builder.INTEGER,
    ),
    "cameo": Dialect(
        "cameo", cameo_builder.ModelBuilder, cameo_builder.End.at,
        cameo_builder.REAL, cameo_builder.BOOLEAN, cameo_builder.INTEGER,
    ),
    "ea": Dialect(
        "ea", ea_builder.ModelBuilder, ea_builder.End.at, ea_builder.REAL, ea_builder.BOOLEAN, ea_builder.INTEGER,
    ),
}  # fmt: skip


# ---- helpers ---------------------------------------------------------------------------------


def port(block: Block, name: str) -> Property:
    """The port ``name`` of ``block``."""
    return next(p for p in block.attributes if p.name == name)


def single_state(block: Block, state: str, pf: Behavior) -> None:
    """An FSM of one initial state whose behaviour runs ``pf`` and never terminates."""
    fsm = block.state_machine()
    fsm.state(state, initial=True).do_activity(tc="FALSE", ec="FALSE").stages([[pf]])


def link(agent: Block, source: tuple[Property, str], target: tuple[Property, str], end_at: Callable[..., Any]) -> None:
    """An inter-subsystem link of ``agent`` from ``source`` to ``target``, each (part, port name)."""
    (src_part, src_port), (dst_part, dst_port) = source, target
    src_type, dst_type = src_part.type, dst_part.type
    agent.connector(
        f"{src_part.name},{dst_part.name}",
        end_at(port(src_type, src_port), src_part),
        end_at(port(dst_type, dst_port), dst_part),
        "InterSubsystemLink",
    )


def inter_agent_link(
    system: Block,
    name: str,
    source: tuple[Block, Sequence[Property]],
    target: tuple[Block, Sequence[Property]],
    message: str,
    end_at: Callable[..., Any],
) -> None:
    """An inter-agent link of ``system`` named ``name`` from ``message/ob`` of the source control
    subsystem to ``message/ib`` of the target one; each end is (cs block, the parts from the system
    down to the cs part)."""
    (src_cs, src_path), (dst_cs, dst_path) = source, target
    system.connector(
        name,
        end_at(port(src_cs, f"{message}/ob"), *src_path),
        end_at(port(dst_cs, f"{message}/ib"), *dst_path),
        "InterAgentLink",
    )


def start_model(dialect: str, name: str, stereotypes: bool = True,
                papyrus_profile: str | None = None) -> tuple[Dialect, ModelBuilder]:
    """The dialect's builder and a new model ``name`` in it; a Papyrus model applies the profile
    at ``papyrus_profile`` (a path relative to the sample) when one is given."""
    kit = DIALECTS[dialect]
    options = {"profile_location": papyrus_profile} if dialect == "papyrus" and papyrus_profile else {}
    return kit, kit.model_builder(name, stereotypes=stereotypes, **options)


def write_dialects(args: Sequence[str], files: Mapping[str, Path], build: Callable[..., bytes], root: Path) -> int:
    """The command line of a sample script: no argument writes every dialect's file of ``files``;
    ``[--dialect papyrus|cameo|ea] OUTPUT`` writes one dialect (Papyrus by default) to ``OUTPUT``."""
    args = list(args)
    dialect = "papyrus"
    if args[:1] == ["--dialect"] and len(args) >= 2:
        dialect, args = args[1], args[2:]
    if dialect not in files:
        print(f"unknown dialect {dialect!r}; choose from {', '.join(files)}", file=sys.stderr)
        return 2
    jobs = [(dialect, Path(args[0]))] if args else list(files.items())
    for name, target in jobs:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(build(dialect=name))
        print(f"wrote {target.relative_to(root) if target.is_relative_to(root) else target}")
    return 0

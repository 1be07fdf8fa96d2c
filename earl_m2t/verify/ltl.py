"""LTL properties over FSM states and primitive predicates, with SPIN's operators.

Two kinds of atom: ``agent/subsystem@state`` (the subsystem is in that state) and
``agent/subsystem.name/pp`` (the primitive predicate ``name/pp`` of that subsystem held in its
latest iteration; false before its first one). The ``/pp`` suffix is required, so a predicate
and a state of the same name (the sample's ``emergencyStop``) are never confused. A model with
a variable structure adds ``config@NAME`` (the configuration holds), ``switching`` (a switch is
pending) and ``agent@active`` (the agent runs; it has no ``.subsystem``, so it is never read as
a state atom).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import EarlModel, Subsystem

_SUBSYSTEM = r"[A-Za-z_]\w*/[A-Za-z]+\.[A-Za-z_]\w*(?:/[A-Za-z]+)?"
_STATE_ATOM = re.compile(rf"({_SUBSYSTEM})@([A-Za-z_]\w*)")
_PREDICATE_ATOM = re.compile(rf"({_SUBSYSTEM})\.([A-Za-z_]\w*/pp)\b")
_CONFIG_ATOM = re.compile(r"config@([A-Za-z_]\w*)")
_AGENT_ATOM = re.compile(r"([A-Za-z_]\w*/[A-Za-z]+)@active\b")
_SWITCHING_ATOM = re.compile(r"switching\b")
_ALLOWED = re.compile(r"\s*(\[\]|<>|!|&&|\|\||->|<->|\(|\)|U\b|V\b|W\b|true\b|false\b)")
_HINT = "write agent/subsystem@state, agent/subsystem.name/pp, [] <> ! && || -> U and parentheses"
_VARIABLE_HINT = ("write agent/subsystem@state, agent/subsystem.name/pp, config@NAME, switching, agent@active, "
                  "[] <> ! && || -> U and parentheses")


class LtlError(Exception):
    """A property that does not parse or names no state: ``str()`` is ``file:line:col: message``."""


@dataclass(frozen=True, slots=True)
class StateAtom:
    subsystem: str  # its path
    state: str


@dataclass(frozen=True, slots=True)
class PredicateAtom:
    subsystem: str  # its path
    predicate: str  # the primitive predicate's name in the model


@dataclass(frozen=True, slots=True)
class ConfigAtom:
    configuration: str  # its name


@dataclass(frozen=True, slots=True)
class AgentAtom:
    agent: str  # its path


@dataclass(frozen=True, slots=True)
class SwitchingAtom:
    pass


Token = str | StateAtom | PredicateAtom | ConfigAtom | AgentAtom | SwitchingAtom


def tokens(prop: LtlProperty, model: EarlModel) -> tuple[Token, ...]:
    """The formula as operators and resolved atoms; raises :class:`LtlError`."""
    return _Tokenizer(prop, model).tokens()


class _Tokenizer:
    def __init__(self, prop: LtlProperty, model: EarlModel) -> None:
        self.prop = prop
        self.model = model

    def tokens(self) -> tuple[Token, ...]:
        out: list[Token] = []
        pos = 0
        text = self.prop.text
        while pos < len(text):
            if text[pos].isspace():
                pos += 1
                continue
            state = _STATE_ATOM.match(text, pos)
            if state:
                out.append(self._state(state.group(1), state.group(2), pos))
                pos = state.end()
                continue
            predicate = _PREDICATE_ATOM.match(text, pos)
            if predicate:
                out.append(self._predicate(predicate.group(1), predicate.group(2), pos))
                pos = predicate.end()
                continue
            atom = self._structure(text, pos)
            if atom is not None:
                out.append(atom[0])
                pos = atom[1]
                continue
            op = _ALLOWED.match(text, pos)
            if not op:
                hint = _VARIABLE_HINT if any(s.configurations for s in self.model.systems) else _HINT
                raise self._error(pos, f"unexpected {text[pos:pos + 12]!r}: {hint}")
            out.append(op.group(1))
            pos = op.end()
        if text.count("(") != text.count(")"):
            raise self._error(len(text), "unbalanced parentheses")
        if not out:
            raise self._error(0, f"the property {self.prop.title} has no formula")
        return tuple(out)

    def _structure(self, text: str, pos: int) -> tuple[Token, int] | None:
        """An atom of the variable structure at ``pos`` and where it ends, None when there is none."""
        config = _CONFIG_ATOM.match(text, pos)
        if config:
            names = [c.name for s in self.model.systems for c in s.configurations]
            if config.group(1) not in names:
                known = ", ".join(names) or "none"
                raise self._error(pos, f"no configuration {config.group(1)} (the model has: {known})")
            return ConfigAtom(config.group(1)), config.end()
        agent = _AGENT_ATOM.match(text, pos)
        if agent:
            if not any(a.path == agent.group(1) for a in self.model.agents):
                raise self._error(pos, f"no agent {agent.group(1)}")
            return AgentAtom(agent.group(1)), agent.end()
        switching = _SWITCHING_ATOM.match(text, pos)
        return (SwitchingAtom(), switching.end()) if switching else None

    def _state(self, path: str, state: str, pos: int) -> StateAtom:
        subsystem = self.model.subsystem(path)
        fsm = subsystem.fsm if subsystem is not None else None
        if fsm is None or fsm.state(state) is None:
            raise self._error(pos, f"no state {state} of a subsystem {path}")
        return StateAtom(path, state)

    def _predicate(self, path: str, written: str, pos: int) -> PredicateAtom:
        subsystem = self.model.subsystem(path)
        if subsystem is None:
            raise self._error(pos, f"no subsystem {path} (for its predicate {written})")
        name = predicate_name(subsystem, written)
        if name is None:
            known = ", ".join(p.name for p in subsystem.predicates) or "none"
            raise self._error(pos, f"no primitive predicate {written} of the subsystem {path} (it has: {known})")
        return PredicateAtom(path, name)

    def _error(self, offset: int, message: str) -> LtlError:
        loc = self.prop.location
        column = (loc.column or 1) + offset
        if loc.line == 0:
            return LtlError(f"{loc.file}: {self.prop.title}: column {column}: {message}")
        return LtlError(f"{loc.file}:{loc.line}:{column}: {message}")


def predicate_name(subsystem: Subsystem, written: str) -> str | None:
    """The model's name of the primitive predicate written ``name/pp`` (models may leave out ``/pp``)."""
    stem = written.removesuffix("/pp")
    names = {p.name for p in subsystem.predicates}
    return next((n for n in (written, stem) if n in names), None)

"""LTL properties over FSM states and primitive predicates, with SPIN's operators.

Two kinds of atom: ``agent/subsystem@state`` (the subsystem is in that state) and
``agent/subsystem.name/pp`` (the primitive predicate ``name/pp`` of that subsystem held in its
latest iteration; false before its first one). The ``/pp`` suffix is required, so a predicate
and a state of the same name (the sample's ``emergencyStop``) are never confused.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import EarlModel, Subsystem

_SUBSYSTEM = r"[A-Za-z_]\w*/[A-Za-z]+\.[A-Za-z_]\w*(?:/[A-Za-z]+)?"
_STATE_ATOM = re.compile(rf"({_SUBSYSTEM})@([A-Za-z_]\w*)")
_PREDICATE_ATOM = re.compile(rf"({_SUBSYSTEM})\.([A-Za-z_]\w*/pp)\b")
_ALLOWED = re.compile(r"\s*(\[\]|<>|!|&&|\|\||->|<->|\(|\)|U\b|V\b|W\b|true\b|false\b)")
_HINT = "write agent/subsystem@state, agent/subsystem.name/pp, [] <> ! && || -> U and parentheses"


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


Token = str | StateAtom | PredicateAtom


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
            op = _ALLOWED.match(text, pos)
            if not op:
                raise self._error(pos, f"unexpected {text[pos:pos + 12]!r}: {_HINT}")
            out.append(op.group(1))
            pos = op.end()
        if text.count("(") != text.count(")"):
            raise self._error(len(text), "unbalanced parentheses")
        if not out:
            raise self._error(0, f"the property {self.prop.title} has no formula")
        return tuple(out)

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

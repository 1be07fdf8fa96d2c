"""LTL properties over FSM states: ``agent/subsystem@state`` atoms with SPIN's operators."""

from __future__ import annotations

import re
from dataclasses import dataclass

from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location

_ATOM = re.compile(r"([A-Za-z_][\w]*/[A-Za-z]+\.[A-Za-z_][\w]*(?:/[A-Za-z]+)?)@([A-Za-z_]\w*)")
_ALLOWED = re.compile(r"\s*(\[\]|<>|!|&&|\|\||->|<->|\(|\)|U\b|V\b|W\b|true\b|false\b)")


class LtlError(Exception):
    """A property that does not parse or names no state: ``str()`` is ``file:line:col: message``."""


@dataclass(frozen=True, slots=True)
class LtlProperty:
    name: str  # the identifier SPIN knows it by
    text: str
    location: Location
    label: str = ""  # the name the model gives it

    @property
    def title(self) -> str:
        return self.label or self.name

    def promela(self, model: EarlModel) -> str:
        from earl_m2t.verify.promela import translate

        spec = translate(model)
        out: list[str] = []
        pos = 0
        text = self.text
        while pos < len(text):
            atom = _ATOM.match(text, pos) if not text[pos].isspace() else None
            if atom:
                sub_path, state = atom.group(1), atom.group(2)
                info = spec.state_variable(sub_path)
                subsystem = model.subsystem(sub_path)
                fsm = subsystem.fsm if subsystem is not None else None
                if fsm is None or fsm.state(state) is None:
                    raise self._error(pos, f"no state {state} of a subsystem {sub_path}")
                number = [s.name for s in fsm.states].index(state)
                # a subsystem left out never leaves its initial state
                out.append(f"({info.variable} == {number})" if info else ("true" if fsm.initial == state else "false"))
                pos = atom.end()
                continue
            op = _ALLOWED.match(text, pos)
            if not op or op.end() == pos:
                if text[pos].isspace():
                    pos += 1
                    continue
                raise self._error(pos, f"unexpected {text[pos:pos + 12]!r}: write agent/subsystem@state, "
                                       "[] <> ! && || -> U and parentheses")
            out.append(op.group(1))
            pos = op.end()
        if text.count("(") != text.count(")"):
            raise self._error(len(text), "unbalanced parentheses")
        return " ".join(out)

    def _error(self, offset: int, message: str) -> LtlError:
        loc = self.location
        column = (loc.column or 1) + offset
        if loc.line == 0:
            return LtlError(f"{loc.file}: {self.title}: column {column}: {message}")
        return LtlError(f"{loc.file}:{loc.line}:{column}: {message}")

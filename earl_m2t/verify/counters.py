"""Tracked Input Buffers as counters of the values waiting, and their Promela statements.

A buffer counts as one byte; in a variable-structure model a buffer that a variable link
delivers to counts per link (what a switch clears is then told per link), each send guarded by
its link being open; a send that a closed link drops while its leaving sender drains sets
``dropped`` (switching.DROP).
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.elements import Buffer, Link
from earl_m2t.verify.promela_text import promela_comment
from earl_m2t.verify.switching import DROP, SWITCH_MARK


@dataclass(frozen=True, slots=True)
class CountedLink:
    link: Link
    variable: str
    open: str | None  # the Promela condition under which it delivers, None when always
    drops: str | None = None  # when a send it refuses is dropped (disjoint from open), None when never


@dataclass(frozen=True, slots=True)
class TrackedBuffer:
    buffer: Buffer
    variable: str  # its counter, or its first link's
    capacity: int
    links: tuple[CountedLink, ...] = ()  # counted per link (variable structure only)

    @property
    def count(self) -> str:
        """The number of values waiting."""
        if len(self.links) > 1:
            return "(" + " + ".join(c.variable for c in self.links) + ")"
        return self.variable

    @property
    def counters(self) -> tuple[tuple[str, str], ...]:
        """Each counter and what it counts (a link, or the buffer)."""
        if self.links:
            return tuple((c.variable, c.link.path) for c in self.links)
        return ((self.variable, self.buffer.path),)

    def declarations(self) -> list[str]:
        if not self.links:
            return [f"byte {self.variable} = 0; /* {promela_comment(self.buffer.path)}, up to {self.capacity} */"]
        return [f"byte {c.variable} = 0; /* {promela_comment(self.buffer.path)} by {promela_comment(c.link.path)}, "
                f"up to {self.capacity} */"
                for c in self.links]

    def receive(self) -> str:
        """One iteration receives: a queue gives its oldest value, a latest buffer its one value."""
        if len(self.links) <= 1:
            v = self.variable
            return f"{v} = ({v} > 0 -> {v} - 1 : 0)" if self.capacity > 1 else f"{v} = 0"
        if self.capacity == 1:
            return "; ".join(f"{c.variable} = 0" for c in self.links)
        choices = " ".join(f":: {c.variable} > 0 -> {c.variable}--" for c in self.links)
        return f"if {choices} :: else -> skip fi"

    def sending(self, links: frozenset[str]) -> tuple[CountedLink, ...]:
        return tuple(c for c in self.links if c.link.path in links)

    def can_send(self, links: frozenset[str]) -> str:
        """A send on ``links`` would change the count, or drop the value."""
        if not self.links:
            return f"{self.variable} < {self.capacity}"
        return " || ".join(f"{_open(c)}{self.count} < {self.capacity}" + (f" || {c.drops}" if c.drops else "")
                           for c in self.sending(links)) or "false"

    def send(self, links: frozenset[str]) -> list[str]:
        """Sends on ``links`` (a full queue drops the value, as the runtime's overflow)."""
        if not self.links:
            v = self.variable
            return [f"{v} = ({v} < {self.capacity} -> {v} + 1 : {self.capacity})"]
        out = []
        for c in self.sending(links):
            dropped = f" :: {c.drops} -> {DROP.format(mark=SWITCH_MARK, counter=c.variable)}" if c.drops else ""
            if self.capacity == 1:  # latest: the newest value supersedes the others
                others = "".join(f"; {o.variable} = 0" for o in self.links if o is not c)
                out.append(f"if :: {_open(c, '')} -> {c.variable} = 1{others}{dropped} :: else -> skip fi")
            else:
                out.append(f"if :: {_open(c)}{self.count} < {self.capacity} -> {c.variable}++{dropped} "
                           ":: else -> skip fi")
        return out


def _open(c: CountedLink, joiner: str = " && ") -> str:
    if c.open is None:
        return "" if joiner else "true"
    return f"{c.open}{joiner}" if joiner else c.open

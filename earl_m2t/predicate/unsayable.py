"""A condition that a source model states in a form the predicate language cannot say.

A reader that meets one (a SysML v2 expression with a string literal, ``null``, or ``q#(0)``)
keeps it as the text ``<reason>``, which is no predicate, so that the condition rules report it
(B008) with the reason, at the condition's place, instead of dropping it.
"""

from __future__ import annotations

_OPEN, _CLOSE = "<", ">"


def unsayable(reason: str) -> str:
    """The condition text standing for a condition the predicate language cannot say."""
    return f"{_OPEN}{reason}{_CLOSE}"


def unsayable_reason(text: str) -> str | None:
    """The reason kept by :func:`unsayable`, or None for any other text (markup such as
    ``<b>x</b>`` included: it is reported as the syntax error it is)."""
    stripped = text.strip()
    inner = stripped[1:-1]
    if len(stripped) > 2 and stripped[0] == _OPEN and stripped[-1] == _CLOSE and _OPEN not in inner:
        return inner
    return None

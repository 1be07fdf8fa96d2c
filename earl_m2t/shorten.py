"""Long values shortened for messages: a 30,000-character name is shown by its ends and its length.

Models are untrusted input; a name or href of any length may reach a finding or an error. Messages
stay readable one-liners: a value over ``LIMIT`` characters keeps its first and last characters
and says how long it was, ``AAAA…AAAA (30000 characters)``.
"""

from __future__ import annotations

import re

LIMIT = 120
_HEAD, _TAIL = 48, 24
_LONG_WORD = re.compile(rf"\S{{{LIMIT + 1},}}")


def shortened(value: str, limit: int = LIMIT) -> str:
    """``value`` when at most ``limit`` characters, else its ends and its length."""
    if len(value) <= limit:
        return value
    head, tail = min(_HEAD, limit // 2), min(_TAIL, limit // 4)
    return f"{value[:head]}…{value[len(value) - tail:]} ({len(value)} characters)"


def shortened_words(text: str) -> str:
    """Every run of more than ``LIMIT`` non-blank characters of ``text`` shortened (a message's names, hrefs, paths)."""
    if len(text) <= LIMIT:
        return text
    return _LONG_WORD.sub(lambda match: shortened(match.group(0)), text)

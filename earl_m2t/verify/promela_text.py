"""Model text on its way into Promela: the one place that makes a name safe where the
translation writes it."""

from __future__ import annotations


def promela_comment(text: str) -> str:
    """Text safe inside a ``/* … */`` comment: one line, printable, no comment delimiter."""
    flat = " ".join("".join(c if c.isprintable() else " " for c in text).split())
    return flat.replace("*/", "* /").replace("/*", "/ *")

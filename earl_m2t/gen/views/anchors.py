"""Stable ids for model elements, as HTML anchors and diagram file names.

An element's id is its element path with every run of characters other than ASCII letters
and digits replaced by ``-``: ``manip/a.cs`` → ``manip-a-cs``,
``manip/a.cs.fsm.idle,jointMove/t`` → ``manip-a-cs-fsm-idle-jointMove-t``. Replicated
subsystems are one definition and take the path of their template
(``manip/a.motorControllerK/ve`` → ``manip-a-motorControllerK-ve``); each instance path
resolves to it. An id already taken in one document gets ``-2``, ``-3`` … in model order.
"""

from __future__ import annotations

import re

_NOT_ID = re.compile(r"[^A-Za-z0-9]+")


def slug(path: str) -> str:
    """The id text of an element path (never empty)."""
    return _NOT_ID.sub("-", path).strip("-") or "element"


class AnchorIndex:
    """The ids of one document: element paths → unique ids, and finding paths → the nearest id."""

    def __init__(self) -> None:
        self._by_path: dict[str, str] = {}
        self._taken: set[str] = set()
        self._last_number: dict[str, int] = {}

    def add(self, path: str, *aliases: str) -> str:
        """The id of ``path`` (assigned on first use); ``aliases`` (instance paths) resolve to it."""
        if path in self._by_path:
            anchor = self._by_path[path]
        else:
            base = slug(path)
            anchor, number = base, 1
            if anchor.lower() in self._taken:  # numbering resumes where this base's last ended: linear
                number = self._last_number.get(base.lower(), 1)
                while anchor.lower() in self._taken:
                    number += 1
                    anchor = f"{base}-{number}"
                self._last_number[base.lower()] = number
            self._taken.add(anchor.lower())
            self._by_path[path] = anchor
        for alias in aliases:
            self._by_path.setdefault(alias, anchor)
        return anchor

    def get(self, path: str) -> str:
        return self._by_path[path]

    def nearest(self, path: str) -> str:
        """The id of ``path`` or of its closest enclosing element ("" when none is known)."""
        candidate = path
        while candidate:
            if candidate in self._by_path:
                return self._by_path[candidate]
            head, dot, _tail = candidate.rpartition(".")
            candidate = head if dot else ""
        return ""

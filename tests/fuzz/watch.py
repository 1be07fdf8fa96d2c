"""What the campaign's parent reads of a worker from /proc to tell a hang from a slow machine:
its CPU time, and whether it (or a process it started) is running or waiting for a CPU."""

from __future__ import annotations

import os
from pathlib import Path

_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid: int) -> float:
    """User and system CPU time of a running process (0 when it cannot be read)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as stream:
            fields = stream.read().rsplit(b")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / _TICKS
    except (OSError, IndexError, ValueError):
        return 0.0


def runnable(pid: int) -> bool:
    """A thread of ``pid`` or of a process it started is running or waiting for a CPU (state
    R): the input makes progress, or would on a less busy machine."""
    pending = [pid]
    seen: set[int] = set()
    while pending:
        current = pending.pop()
        if current in seen:
            continue
        seen.add(current)
        for task in _tasks(current):
            if _state(task) == b"R":
                return True
            pending.extend(_children(task))
    return False


def _tasks(pid: int) -> list[Path]:
    try:
        return list(Path(f"/proc/{pid}/task").iterdir())
    except OSError:
        return []


def _state(task: Path) -> bytes:
    try:
        return (task / "stat").read_bytes().rsplit(b")", 1)[1].split()[0]
    except (OSError, IndexError):
        return b""


def _children(task: Path) -> list[int]:
    try:
        return [int(word) for word in (task / "children").read_text().split()]
    except (OSError, ValueError):
        return []

"""The work a piece of code does, counted in Python function calls: deterministic, unlike its
time on a loaded machine, so a test can assert that work grows linearly."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")


def counted_calls(work: Callable[[], T]) -> tuple[T, int]:
    """``work()``'s result and the Python function calls it made (in this thread)."""
    count = 0

    def counter(frame: object, event: str, argument: object) -> None:
        nonlocal count
        if event == "call":
            count += 1

    sys.setprofile(counter)
    try:
        result = work()
    finally:
        sys.setprofile(None)
    return result, count

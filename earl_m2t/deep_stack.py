"""Run a command with room for deeply nested models.

Reading, lifting and checking walk a model's nesting (packages, states, guard expressions)
recursively. Python's default limit (1,000 frames) and the main thread's stack (8 MiB) would end
a deep but valid model in a ``RecursionError``; a command runs instead in a thread with a
large stack and a recursion limit to match. Readers still refuse nesting deeper than what they
document (the SysML v2 reader: ``MAX_NESTING`` of :mod:`earl_m2t.sysml2.limits`).
"""

from __future__ import annotations

import contextvars
import sys
import threading
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T")

STACK_BYTES = 512 << 20  # virtual address space, touched only as deep as a model needs
RECURSION_LIMIT = 60_000  # about 8 KiB of stack a frame in the worst case fits in STACK_BYTES


def call_with_deep_stack(function: Callable[[], T]) -> T:
    """``function()`` in a thread with a large stack and recursion limit; its result or its exception."""
    outcome: list[T] = []
    failure: list[BaseException] = []
    context = contextvars.copy_context()

    def run() -> None:
        try:
            outcome.append(context.run(function))
        except BaseException as exc:  # handed to the caller's thread, raised there
            failure.append(exc)

    previous_stack = threading.stack_size()
    previous_limit = sys.getrecursionlimit()
    sys.setrecursionlimit(max(previous_limit, RECURSION_LIMIT))
    try:
        threading.stack_size(STACK_BYTES)
        try:
            worker = threading.Thread(target=run, name="earl-m2t")
            worker.start()
        finally:
            threading.stack_size(previous_stack)
        worker.join()
    finally:
        sys.setrecursionlimit(previous_limit)
    if failure:
        raise failure[0]
    return outcome[0]

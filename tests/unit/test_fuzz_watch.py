"""How the fuzz campaign tells a blocked input (a hang) from a starved one (a busy machine):
tests/fuzz/watch.py and the runner's per-worker bookkeeping."""

from __future__ import annotations

import multiprocessing
import subprocess
import sys
import time
from typing import Any

from tests.fuzz.runner import LONGEST_LOOK_GAP, _Slot
from tests.fuzz.watch import runnable

SPIN = "while True: pass"


def test_a_spinning_process_is_runnable_a_sleeping_one_is_not() -> None:
    sleeping = subprocess.Popen(["sleep", "30"])
    spinning = subprocess.Popen([sys.executable, "-c", SPIN])
    try:
        time.sleep(0.3)
        assert runnable(spinning.pid)
        assert not runnable(sleeping.pid)
    finally:
        for process in (sleeping, spinning):
            process.kill()
            process.wait()


def test_a_process_waiting_for_a_child_that_works_is_runnable() -> None:
    parent = subprocess.Popen([sys.executable, "-c",
                               f"import subprocess, sys; subprocess.run([sys.executable, '-c', {SPIN!r}])"])
    try:
        time.sleep(0.5)
        assert runnable(parent.pid)
    finally:
        subprocess.run(["pkill", "-KILL", "-P", str(parent.pid)], check=False)
        parent.kill()
        parent.wait()


def _sleep() -> None:
    time.sleep(30)


def _spin() -> None:
    while True:
        pass


def test_a_worker_counts_blocked_time_only_while_it_neither_runs_nor_waits_for_a_cpu() -> None:
    context = multiprocessing.get_context("fork")
    slots = {}
    for name, target in (("sleeping", _sleep), ("spinning", _spin)):
        process = context.Process(target=target, daemon=True)
        process.start()
        parent, _ = context.Pipe()
        slots[name] = _Slot(process, parent, 0)
    try:
        for _ in range(6):
            time.sleep(0.2)
            for slot in slots.values():
                slot.watch()
        assert slots["sleeping"].blocked >= 0.8
        assert slots["spinning"].blocked == 0.0
    finally:
        for slot in slots.values():
            slot.process.kill()
            slot.process.join()


def test_a_pause_of_the_campaign_itself_is_not_counted_as_blocked() -> None:
    """The campaign stopped with its process group (``kill -STOP``, to free the machine for a
    while) and resumed: its first look at a sleeping worker comes long after the last one, and
    that gap must not make a hang of the input the worker runs."""
    context = multiprocessing.get_context("fork")
    process = context.Process(target=_sleep, daemon=True)
    process.start()
    parent, _ = context.Pipe()
    slot = _Slot(process, parent, 0)
    try:
        time.sleep(0.2)
        slot._looked -= 3600.0  # the parent's last look, an hour before it was resumed
        slot.watch()
        assert 0.0 < slot.blocked <= LONGEST_LOOK_GAP
    finally:
        process.kill()
        process.join()


def _commands(started: Any, count: int, seconds: float) -> None:
    """``count`` commands one after the other, each spinning for ``seconds`` of CPU time."""
    for _ in range(count):
        started.value += 1
        until = time.process_time() + seconds
        while time.process_time() < until:
            pass
    time.sleep(30)


def _cpu_counted(count: int, seconds: float) -> float:
    """The largest CPU time the parent's bookkeeping counted against one command of a worker."""
    context = multiprocessing.get_context("fork")
    started = context.RawValue("Q", 0)
    process = context.Process(target=_commands, args=(started, count, seconds), daemon=True)
    process.start()
    parent, _ = context.Pipe()
    slot = _Slot(process, parent, 0, 0.0, started)
    largest = 0.0
    try:
        deadline = time.monotonic() + count * seconds * 20 + 5
        while started.value < count or slot.watch() - slot.cpu_since < seconds * 0.9:
            time.sleep(0.05)
            largest = max(largest, slot.watch() - slot.cpu_since)
            assert time.monotonic() < deadline, "the worker did not run its commands"
        return max(largest, slot.watch() - slot.cpu_since)
    finally:
        process.kill()
        process.join()


def test_the_bound_is_per_command_not_per_input() -> None:
    """An input runs several commands (a clean check, then every target's gen): five commands of
    0.4 s of CPU time each count at most about 0.4 s against the bound, one of 2 s counts 2 s."""
    assert _cpu_counted(5, 0.4) < 1.0
    assert _cpu_counted(1, 2.0) >= 1.8

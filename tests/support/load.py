"""Runs under load: one busy process per CPU while a test runs, and a run read line by line that
stops as soon as the states it waits for were printed.

The loaded campaigns (threaded C++, ROS launch, Orocos deployer) use these so that a run that
only passes on an idle machine, or with a lucky schedule, fails.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager, nullcontext
from pathlib import Path

HOG = "while True:\n    pass\n"
POLL_SECONDS = 0.2


@contextmanager
def cpu_hogs(count: int | None = None) -> Iterator[list[subprocess.Popen[bytes]]]:
    """``count`` (default: one per CPU) processes spinning at full speed, stopped on exit
    whatever happens inside."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        raise RuntimeError("a loaded test runs alone on the machine: mark it @pytest.mark.loaded, which "
                           "./dev test runs after the parallel tests, one at a time")
    hogs: list[subprocess.Popen[bytes]] = []
    try:
        for _ in range(count or os.cpu_count() or 2):
            hogs.append(subprocess.Popen([sys.executable, "-c", HOG], stdin=subprocess.DEVNULL,
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        yield hogs
    finally:
        for hog in hogs:
            hog.kill()
        for hog in hogs:
            hog.wait()


def line_buffered(command: Sequence[str | Path]) -> list[str]:
    """``command`` with its stdout line-buffered when coreutils' stdbuf is there (printf to a
    pipe is block-buffered, and the run is stopped before it would flush)."""
    stdbuf = shutil.which("stdbuf")
    return ([stdbuf, "-oL"] if stdbuf else []) + [str(c) for c in command]


def run_until(command: Sequence[str | Path], seen: Callable[[list[str]], bool], timeout: float,
              env: dict[str, str] | None = None, cwd: Path | None = None,
              graceful: bool = True, stderr: Path | None = None) -> tuple[list[str], bool]:
    """Run ``command`` and read its output (stdout, and stderr unless ``stderr`` names a file to
    write it to) line by line until ``seen(lines)`` holds or ``timeout`` seconds passed; then
    stop it, its whole process group: with SIGINT first when ``graceful``, else at once with
    SIGKILL (nothing of the run is needed after ``seen``). Returns the lines and whether
    ``seen`` held.

    A program whose logger writes a line in pieces to unbuffered stderr (RTT's writes its time
    and level, then the message) gets a line printed by another thread in between when both
    streams share one pipe: give such a program's stderr a file of its own."""
    with open(stderr, "wb") if stderr else nullcontext(subprocess.STDOUT) as error_output:
        process = subprocess.Popen(line_buffered(command), stdout=subprocess.PIPE, stderr=error_output,
                                   stdin=subprocess.DEVNULL, env=env, cwd=cwd, text=True, start_new_session=True)
    lines: list[str] = []
    done = threading.Event()
    asking = threading.Lock()  # ``seen`` is never asked from two threads at once

    def holds() -> bool:
        with asking:
            return seen(lines)

    def read() -> None:
        assert process.stdout is not None
        for line in process.stdout:
            lines.append(line.rstrip("\n"))
            if holds():
                break
        done.set()

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    deadline = time.monotonic() + timeout
    # ``seen`` is asked between lines as well, so that it may decide on the time passed too (a
    # run that has printed nothing new for a while has shown what it will show)
    while not done.wait(max(0.0, min(POLL_SECONDS, deadline - time.monotonic()))):
        if time.monotonic() >= deadline or holds():
            break
    ok = holds()
    stop(process, graceful)
    reader.join(5)
    return lines, ok


def descendants(pid: int) -> list[int]:
    """Every process started, directly or not, by ``pid`` (from /proc), children first."""
    parents: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rpartition(")")[2].split()
        except OSError:
            continue
        parents.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    found: list[int] = []
    frontier = [pid]
    while frontier:
        children = parents.get(frontier.pop(), [])
        found.extend(children)
        frontier.extend(children)
    return found


def stop(process: subprocess.Popen[str], graceful: bool = True) -> None:
    """Graceful: SIGINT to the process group (a launch or deployer shuts down), then SIGKILL.
    Otherwise SIGKILL at once to it and every process it started, even those in sessions of
    their own (roslaunch starts its nodes so)."""
    if not graceful:
        for pid in [*descendants(process.pid), process.pid]:
            try:
                os.kill(pid, 9)
            except ProcessLookupError:
                pass
        process.wait()
        return
    if process.poll() is not None:
        return
    started = [(pid, _start_time(pid)) for pid in descendants(process.pid)]  # nodes in sessions of their own
    try:
        os.killpg(process.pid, 2)
        process.wait(5)
    except (ProcessLookupError, subprocess.TimeoutExpired):
        pass
    if process.poll() is None:
        try:
            os.killpg(process.pid, 9)
        except ProcessLookupError:
            pass
        process.wait()
    for pid, began in started:  # what the launch did not stop in time (it was killed, or lost a node)
        if began is not None and _start_time(pid) == began:  # the same process, not a reused pid
            try:
                os.kill(pid, 9)
            except ProcessLookupError:
                pass


def _start_time(pid: int) -> int | None:
    """When ``pid`` started (clock ticks since boot), None when it is gone."""
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rpartition(")")[2].split()[19])
    except (OSError, IndexError, ValueError):
        return None

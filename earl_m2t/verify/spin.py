"""Running the real SPIN: ``spin -a``, the system C compiler on ``pan.c``, ``pan``, and the replay
of a trail."""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path

SPEC = "model.pml"


class SpinUnavailable(Exception):
    """``spin`` or a C compiler is not installed, or SPIN rejected the specification."""


class OutOfTime(Exception):
    """A step of SPIN did not finish within the time left."""


@dataclass(frozen=True, slots=True)
class PanRun:
    output: str
    errors: int
    states: int  # states stored
    transitions: int
    depth: int  # depth reached
    complete: bool  # the search was not cut short by the depth, memory or time bound
    interrupted: bool  # the time ran out
    unreached: frozenset[int]  # lines of the specification never executed


def tools() -> tuple[str, str]:
    spin = shutil.which("spin")
    compiler = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if spin is None:
        raise SpinUnavailable("SPIN is not installed (Debian package spin)")
    if compiler is None:
        raise SpinUnavailable("no C compiler (cc) to compile SPIN's pan.c")
    return spin, compiler


def build(folder: Path, text: str, binary: str, flags: tuple[str, ...], seconds: float) -> Path:
    """Writes the specification, generates pan.c and compiles it to ``binary``."""
    spin, compiler = tools()
    (folder / SPEC).write_text(text, encoding="utf-8")
    _call([spin, "-a", SPEC], folder, seconds, "spin -a")
    _call([compiler, "-O1", "-w", *flags, "-o", binary, "pan.c"], folder, seconds, "cc pan.c")
    return folder / binary


def search(binary: Path, args: tuple[str, ...], seconds: float) -> PanRun:
    """Runs pan; when the time runs out it is interrupted, and prints what it explored so far."""
    if seconds <= 0:
        raise OutOfTime("pan")
    interrupted = False
    with subprocess.Popen([str(binary), *args], cwd=binary.parent, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True) as pan:
        try:
            output, _ = pan.communicate(timeout=seconds)
        except subprocess.TimeoutExpired:
            interrupted = True
            pan.send_signal(signal.SIGINT)
            try:
                output, _ = pan.communicate(timeout=30)
            except subprocess.TimeoutExpired:
                pan.kill()
                output, _ = pan.communicate()
    errors = 0 if interrupted else int(_number(r"errors: (\d+)", output))
    lowered = output.lower()
    incomplete = interrupted or "max search depth too small" in output or "out of memory" in lowered \
        or "aborted" in lowered or "interrupted" in lowered
    return PanRun(
        output=output,
        errors=errors,
        states=int(_number(r"(\d+) states, stored", output)),
        transitions=int(_number(r"(\d+) transitions", output)),
        depth=int(_number(r"depth reached (\d+)", output)),
        complete=not incomplete,
        interrupted=interrupted,
        unreached=frozenset(int(n) for n in re.findall(rf"{re.escape(SPEC)}:(\d+), state", output)),
    )


def replay(folder: Path, seconds: float) -> str:
    spin, _ = tools()
    return _call([spin, "-t", SPEC], folder, seconds, "spin -t")


def _number(pattern: str, text: str) -> str:
    match = re.search(pattern, text)
    return match.group(1) if match else "0"


def _call(command: list[str], folder: Path, seconds: float, what: str) -> str:
    if seconds <= 0:
        raise OutOfTime(what)
    try:
        done = subprocess.run(command, cwd=folder, capture_output=True, text=True, timeout=seconds, check=False)
    except subprocess.TimeoutExpired as exc:
        raise OutOfTime(what) from exc
    if done.returncode != 0 and what != "pan":
        detail = (done.stdout + done.stderr).strip().splitlines()
        raise SpinUnavailable(f"{what} failed: {detail[0] if detail else done.returncode}")
    return done.stdout + done.stderr

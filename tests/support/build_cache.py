"""Generated workspaces built once per content: a sample × a target × its build flags.

Many tests build the same generated code: the two_arm C++ for its own campaign and for the
switch sequence the ROS 1, ROS 2 and Orocos campaigns compare with, the pick_and_place ROS 2
workspace for its launch, parameter and graph tests. :func:`built` copies a prepared source tree
into ``${XDG_CACHE_HOME:-~/.cache}/earl-m2t/builds/<kind>-<key>`` and runs the real build there
(CMake, catkin_make, colcon) once; every later call with the same content, in this run or a
later one, gets that folder. ``<key>`` hashes every file of the source tree (names, contents,
the executable bit), the build command and what the build ran against (the compiler's version,
the ROS 2 or RTT prefix, which carry their own source hashes): a changed template, runtime
header, user file or flag is a new key and a new build, so what a test runs is what a fresh
build of that content gives. The folder is not relocatable (colcon and catkin write absolute
paths): it is built where it is used.

A build that fails leaves no entry and fails the calling test with its output; the next call
builds again. Entries are read-only by convention: a test that changes a workspace (regenerates
it, edits a file) takes a source tree of its own, which is a new key. The most recently used
:data:`KEEP` entries are kept; older ones are removed when a new entry is written, except those
a live test process uses: a process holds a shared lock on every entry it was handed until it
exits, so an entry a module fixture holds is never pruned under it by the other worker.
``EARL_BUILD_CACHE=0`` builds in a fresh temporary folder every time instead.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import stat
import subprocess
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import IO

KEEP = 40
COMPLETE = ".earl-build-complete"
# shared locks on the entries this process was handed, held until it exits
_IN_USE: dict[Path, IO[str]] = {}
SOURCE = "src"
# files gen writes that no build reads: the source map names the model's absolute path
IGNORED = frozenset({".earl-trace.json"})


def cache_root() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "earl-m2t" / "builds"


def enabled() -> bool:
    return os.environ.get("EARL_BUILD_CACHE") != "0"


def compiler_identity() -> str:
    """g++'s and cmake's first lines: a new toolchain builds again."""
    lines = []
    for tool in ("g++", "cmake"):
        if shutil.which(tool):
            lines.append(subprocess.run([tool, "--version"], capture_output=True, text=True).stdout.split("\n")[0])
    return "; ".join(lines)


def tree_digest(source: Path) -> str:
    """Every file and link under ``source``: its relative path, whether executable, its content."""
    digest = hashlib.sha256()
    for path in sorted(source.rglob("*")):
        relative = path.relative_to(source).as_posix()
        if path.name in IGNORED or path.is_dir() and not path.is_symlink():
            continue
        digest.update(relative.encode() + b"\0")
        if path.is_symlink():
            digest.update(b"link\0" + os.readlink(path).encode())
        else:
            executable = bool(path.stat().st_mode & stat.S_IXUSR)
            digest.update(b"x" if executable else b"-")
            digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def key_of(kind: str, source: Path, recipe: Sequence[str]) -> str:
    digest = hashlib.sha256()
    for part in (kind, tree_digest(source), compiler_identity(), *recipe):
        digest.update(part.encode() + b"\0")
    return digest.hexdigest()[:20]


def built(kind: str, source: Path, build: Callable[[Path], object], recipe: Sequence[str] = ()) -> Path:
    """The folder holding ``source`` as ``src/`` and what ``build(folder)`` made beside it.

    ``kind`` names the entry (``ros2-two_arm``), ``recipe`` is everything besides the source
    tree that decides what the build makes: its command and flags, the prefix it builds against."""
    if not enabled():
        folder = Path(tempfile.mkdtemp(prefix=f"earl-build-{kind}-"))
        shutil.copytree(source, folder / SOURCE, symlinks=True)
        build(folder)
        return folder
    folder = cache_root() / f"{kind}-{key_of(kind, source, recipe)}"
    folder.parent.mkdir(parents=True, exist_ok=True)
    with open(folder.with_name(folder.name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # a concurrent test process builds it once, the other waits
        stamp = folder / COMPLETE
        if stamp.is_file():
            os.utime(stamp)
            _hold(folder)
            return folder
        shutil.rmtree(folder, ignore_errors=True)  # what a build that failed or was killed left
        shutil.copytree(source, folder / SOURCE, symlinks=True)
        started = time.monotonic()
        build(folder)
        stamp.write_text(f"{kind}\n{time.monotonic() - started:.1f} s\n")
        _hold(folder)
    prune()
    return folder


def _use_lock(folder: Path) -> Path:
    return folder.with_name(folder.name + ".use")


def _hold(folder: Path) -> None:
    """Take a shared lock on ``folder``'s use file and keep it for the life of this process."""
    if folder in _IN_USE:
        return
    handle = open(_use_lock(folder), "a")
    fcntl.flock(handle, fcntl.LOCK_SH)
    _IN_USE[folder] = handle


def release(folder: Path) -> None:
    """This process no longer uses ``folder``: a later prune may remove it."""
    handle = _IN_USE.pop(folder, None)
    if handle is not None:
        handle.close()


def prune(keep: int = KEEP) -> None:
    """Remove all but the ``keep`` most recently used complete entries, and the leftovers of
    builds no process holds the lock of."""
    root = cache_root()
    entries = sorted((p for p in root.iterdir() if p.is_dir()),
                     key=lambda p: (p / COMPLETE).stat().st_mtime if (p / COMPLETE).is_file() else 0.0,
                     reverse=True)
    for folder in entries[keep:]:
        if folder in _IN_USE:
            continue
        lock_path, use_path = folder.with_name(folder.name + ".lock"), _use_lock(folder)
        with open(lock_path, "w") as lock, open(use_path, "a") as use:
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
                fcntl.flock(use, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                continue  # being built, or handed to a test process that is still running
            shutil.rmtree(folder, ignore_errors=True)
        lock_path.unlink(missing_ok=True)
        use_path.unlink(missing_ok=True)

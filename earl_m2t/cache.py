"""An on-disk cache for what earl-m2t derives from its own data files (the parsed profile,
the compiled rule invariants, the predicate texts parsed with the predicate grammar), so a
command does not re-parse them on every start.

Entries are keyed by a hash of the source file, the earl-m2t version, the Python version and
the size and modification time of earl-m2t's own modules (so a changed loader in a working copy
does not read what an older one cached); a stale or unreadable entry is rebuilt. The cache
lives in ``$XDG_CACHE_HOME/earl-m2t`` (``~/.cache/earl-m2t``); ``EARL_M2T_NO_CACHE=1`` turns it
off. Failing to write it is not an error. Each kind of entry keeps its ``KEPT_PER_KIND`` most
recently used entries: a hit refreshes an entry's time, and a write removes the oldest beyond
that, so the entries of past versions and edited sources do not pile up.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import sys
import tempfile
from collections.abc import Callable
from functools import cache
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")

#: entries kept per kind (``name``): enough for the profiles and rule files of a few projects
KEPT_PER_KIND = 24


def cache_dir() -> Path | None:
    if os.environ.get("EARL_M2T_NO_CACHE"):
        return None
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "earl-m2t"


def _code_stamp(folder: Path) -> str:
    """Size and modification time of every module of the package, without reading them."""
    stamps = []
    pending = [folder]
    while pending:
        with os.scandir(pending.pop()) as entries:
            for entry in entries:
                if entry.is_dir(follow_symlinks=False) and entry.name != "__pycache__":
                    pending.append(Path(entry.path))
                elif entry.name.endswith(".py"):
                    status = entry.stat()
                    stamps.append(f"{entry.path}:{status.st_size}:{status.st_mtime_ns}")
    return "|".join(sorted(stamps))


@cache
def _package_stamp() -> str:
    """The stamp of earl-m2t's own modules, taken once per process (every entry's key has it)."""
    return _code_stamp(Path(__file__).parent)


def _key(source: Path) -> str:
    from earl_m2t.version import __version__

    digest = hashlib.sha256(source.read_bytes())
    digest.update(f"{__version__}|{sys.version_info[:3]}|{pickle.HIGHEST_PROTOCOL}".encode())
    digest.update(_package_stamp().encode())
    return digest.hexdigest()[:24]


def cached(name: str, source: Path, build: Callable[[], T]) -> T:
    """The value ``build()`` makes from ``source``, from the cache when it is up to date."""
    found = read_cached(name, source)
    if found is not None:
        return found
    value = build()
    write_cached(name, source, value)
    return value


def read_cached(name: str, source: Path) -> Any:
    """What :func:`write_cached` stored under ``name`` for this ``source``; None when there is
    nothing up to date (or the cache is off or unreadable)."""
    directory = cache_dir()
    if directory is None:
        return None
    try:
        entry = directory / f"{name}-{_key(source)}.pickle"
        with open(entry, "rb") as stream:
            value = pickle.load(stream)  # noqa: S301 - the user's own cache, written below
        os.utime(entry)  # recently used: kept by _prune
        return value
    except (OSError, pickle.UnpicklingError, EOFError, AttributeError, ImportError, TypeError, RecursionError):
        return None


def write_cached(name: str, source: Path, value: object) -> None:
    """Store ``value`` under ``name`` for this ``source``, atomically; failing to is not an error."""
    directory = cache_dir()
    if directory is None:
        return
    temporary = None
    try:
        entry = directory / f"{name}-{_key(source)}.pickle"
        directory.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=directory, prefix=f".{name}-", suffix=".tmp")
        with os.fdopen(handle, "wb") as stream:
            pickle.dump(value, stream, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(temporary, entry)
        temporary = None
        _prune(directory, name)
    except (OSError, pickle.PicklingError, TypeError, AttributeError, RecursionError):
        pass
    finally:
        if temporary is not None:
            try:
                os.unlink(temporary)
            except OSError:
                pass


def _prune(directory: Path, name: str) -> None:
    """Remove the entries of ``name`` beyond the ``KEPT_PER_KIND`` most recently used."""
    entries = []
    for path in directory.glob(f"{name}-*.pickle"):
        try:
            entries.append((path.stat().st_mtime_ns, path.name, path))
        except OSError:  # removed meanwhile by another process
            continue
    for _, _, path in sorted(entries, reverse=True)[KEPT_PER_KIND:]:
        try:
            path.unlink()
        except OSError:
            pass

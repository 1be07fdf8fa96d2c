"""Which files a model may make earl-m2t read, and reading them within bounds.

A model is untrusted input (``check`` runs on pull requests), so every file read because of it
— the model named on the command line and the files its hrefs name — is opened without
blocking and read only when it is a regular file (not a device, FIFO or socket) of at most
``max_bytes`` bytes. A file an href names must also lie, after following links, under one of
the policy's roots: the git work tree that holds the model (else the model's folder), and the
folders given with ``--allow-outside`` or the configuration's ``allow-outside``.
"""

from __future__ import annotations

import contextvars
import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from earl_m2t.diagnostics import ModelReadError

MAX_FILE_BYTES = 1 << 30  # 1 GiB: the limit of a .mdzip member too; far above real models


@dataclass(frozen=True)
class ReadPolicy:
    """The size limit of every file read, and folders outside the model's repository that hrefs may name."""

    max_bytes: int = MAX_FILE_BYTES
    allow_outside: tuple[Path, ...] = ()


_POLICY: contextvars.ContextVar[ReadPolicy] = contextvars.ContextVar("earl_m2t_read_policy", default=ReadPolicy())


def current_policy() -> ReadPolicy:
    return _POLICY.get()


@contextmanager
def reading_with(policy: ReadPolicy) -> Iterator[None]:
    """Read with ``policy`` inside the block (the command line sets it once per command)."""
    token = _POLICY.set(policy)
    try:
        yield
    finally:
        _POLICY.reset(token)


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def open_regular(path: Path | str, shown: str | None = None) -> BinaryIO:
    """``path`` opened for reading, when it is a regular file within the size limit; else :class:`ModelReadError`.

    The file is opened without blocking (a FIFO does not wait for a writer) and checked on the
    open descriptor, so what is checked is what is read.
    """
    file = shown if shown is not None else str(path)
    try:
        descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise ModelReadError(file, "no such file") from None
    except IsADirectoryError:
        raise ModelReadError(file, "is a directory, not a model file") from None
    except OSError as exc:
        raise ModelReadError(file, f"cannot read file: {exc.strerror or exc}") from None
    try:
        info = os.fstat(descriptor)
        if stat.S_ISDIR(info.st_mode):
            raise ModelReadError(file, "is a directory, not a model file")
        if not stat.S_ISREG(info.st_mode):
            raise ModelReadError(file, f"is {_kind(info.st_mode)}, not a regular file: not read")
        limit = current_policy().max_bytes
        if info.st_size > limit:
            raise ModelReadError(file, f"is {info.st_size} bytes, more than the limit of {limit} bytes: not read")
        os.set_blocking(descriptor, True)
        return os.fdopen(descriptor, "rb")
    except BaseException:
        os.close(descriptor)
        raise


def read_regular_bytes(path: Path | str, shown: str | None = None) -> bytes:
    """The bytes of a regular file within the size limit (one more byte than the limit is refused)."""
    file = shown if shown is not None else str(path)
    limit = current_policy().max_bytes
    with open_regular(path, shown) as stream:
        try:
            data = stream.read(limit + 1)
        except OSError as exc:
            raise ModelReadError(file, f"cannot read file: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise ModelReadError(file, f"grew beyond the limit of {limit} bytes while read: not read")
    return data


def work_tree(path: Path) -> Path | None:
    """The git work tree holding ``path`` (a folder with ``.git``, directory or file), or None."""
    folder = path if path.is_dir() else path.parent
    for candidate in (folder, *folder.parents):
        if (candidate / ".git").exists():
            return candidate
    return None


def roots_for(model: Path) -> tuple[Path, ...]:
    """Where files a model references may be: its repository (else its folder) and the allowed folders."""
    real = Path(os.path.realpath(model))
    own = work_tree(real.parent) or real.parent
    extra = tuple(Path(os.path.realpath(folder)) for folder in current_policy().allow_outside)
    return (own, *extra)


def is_under(real: Path, roots: tuple[Path, ...]) -> bool:
    return any(real == root or root in real.parents for root in roots)

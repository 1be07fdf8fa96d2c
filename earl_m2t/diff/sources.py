"""Where the two sides of a diff come from: a file, ``git:REV:PATH`` (a file as committed), or
nothing (``/dev/null``, as git passes for an added or deleted file)."""

from __future__ import annotations

import subprocess
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from earl_m2t.api import load
from earl_m2t.diagnostics import ModelReadError
from earl_m2t.model.elements import EarlModel

GIT_PREFIX = "git:"
NO_FILE = "/dev/null"
# files beside a committed model that it may reference (href="types.uml#…") are taken from
# the same revision
_MODEL_SUFFIXES = (".uml", ".xmi", ".mdzip", ".xml", ".sysml")


@dataclass(frozen=True)
class Side:
    label: str  # as the user named it
    model: EarlModel | None  # None: no model (an added or deleted file)
    read_from: str  # the folder the model was read from, when it is not where the label says ...
    shown_as: str = ""  # ... and how locations in it are shown instead ("git:HEAD:models/")


def empty_side(label: str) -> Side:
    return Side(label, None, "")


@contextmanager
def opened(spec: str, dialect: str | None = None) -> Iterator[Side]:
    """The model ``spec`` names. Raises ModelReadError (one line, exit 2)."""
    if spec == NO_FILE:
        yield empty_side(spec)
        return
    if not spec.startswith(GIT_PREFIX):
        loaded = load(spec, dialect)
        yield Side(spec, loaded.model, "")
        return
    revision, separator, path = spec[len(GIT_PREFIX):].partition(":")
    if not separator or not revision or not path:
        raise ModelReadError(spec, "expected git:REVISION:PATH (e.g. git:HEAD:models/robot.uml)")
    with tempfile.TemporaryDirectory(prefix="earl-m2t-diff-") as folder:
        file = _checkout(revision, path, Path(folder), spec)
        parent = str(PurePosixPath(path).parent)
        shown_as = f"{GIT_PREFIX}{revision}:" + ("" if parent == "." else parent + "/")
        loaded = load(file, dialect)
        yield Side(spec, loaded.model, folder + "/", shown_as)


def _git(args: list[str], spec: str) -> bytes:
    try:
        result = subprocess.run(["git", *args], capture_output=True, check=False)
    except OSError as error:
        raise ModelReadError(spec, f"cannot run git: {error.strerror}") from None
    if result.returncode != 0:
        message = result.stderr.decode("utf-8", "replace").strip().splitlines()
        raise ModelReadError(spec, message[-1] if message else f"git {' '.join(args)} failed")
    return result.stdout


def _checkout(revision: str, path: str, folder: Path, spec: str) -> Path:
    """The committed file, and the model files beside it at that revision, written to ``folder``."""
    wanted = PurePosixPath(path)
    parent = str(wanted.parent) if str(wanted.parent) != "." else ""
    prefix = "./" if path.startswith("./") else ""
    tree = f"{revision}:{prefix}{parent}" if parent else f"{revision}:{prefix}"
    listing = _git(["ls-tree", "-z", "--name-only", tree], spec).decode("utf-8", "replace")
    names = [name for name in listing.split("\0") if name]
    if wanted.name not in names:
        raise ModelReadError(spec, f"{path} is not in revision {revision}")
    for name in names:
        if name == wanted.name or name.lower().endswith(_MODEL_SUFFIXES):
            blob = f"{tree.rstrip('/')}/{name}" if parent or prefix else f"{revision}:{name}"
            try:
                (folder / name).write_bytes(_git(["cat-file", "blob", blob], spec))
            except ModelReadError:
                if name == wanted.name:
                    raise
    return folder / wanted.name

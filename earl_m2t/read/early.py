"""Parsing a model file while the command loads the code that checks it.

lxml parses without holding the interpreter lock, so on a machine with a second core the parse
of the file named on the command line costs no wall time while the interpreter imports the
readers, the rules and the SAT solver (about 0.1 s). :func:`parsing_early` starts it in a
thread; :func:`read_raw_model <earl_m2t.read.xmi_index.read_raw_model>` takes the tree with
:func:`take_parsed` (waiting for it) and indexes it as it would have indexed its own.

The thread reads and parses exactly as the reader does (:mod:`earl_m2t.read.bounded`,
:mod:`earl_m2t.read.safe_xml`): the same size limit and checks of the file, the same parser
options and the same one-line errors, raised again where the tree is taken. It imports nothing,
so it never races the importing thread. A project archive (``.mdzip``), SysML v2 text, or a read
policy changed before the tree is taken leaves the reading to the reader.
"""

from __future__ import annotations

import contextvars
import os
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.bounded import ReadPolicy, current_policy, open_regular
from earl_m2t.read.mdzip import is_archive
from earl_m2t.read.safe_xml import parse_xml_bytes
from earl_m2t.sysml2.files import is_sysml2


@dataclass
class _Parse:
    policy: ReadPolicy
    thread: threading.Thread | None = None
    tree: etree._ElementTree | None = None  # None: not XML the reader parses itself (an archive)
    error: BaseException | None = None  # what the reader would have raised, raised again when taken


_started: dict[str, _Parse] = {}
_lock = threading.Lock()


def _key(path: Path | str) -> str:
    return str(Path(path))


@contextmanager
def parsing_early(path: Path | str | None) -> Iterator[None]:
    """Inside the block, ``path`` is parsed in the background for the reader to take (nothing
    when ``path`` is None, a folder or a SysML v2 file); a parse not taken is dropped at its end."""
    key = _key(path) if path is not None else ""
    if key and not is_sysml2(Path(key)) and os.path.isfile(key):
        _start(key)
    try:
        yield
    finally:
        if key:
            with _lock:
                _started.pop(key, None)


def _start(key: str) -> None:
    job = _Parse(current_policy())
    context = contextvars.copy_context()  # the read policy lives in a context variable
    job.thread = threading.Thread(target=context.run, args=(_parse, key, job), name="earl-m2t-parse",
                                  daemon=True)
    with _lock:
        _started[key] = job  # replaces a parse of an earlier command nobody took
    job.thread.start()


def _parse(file: str, job: _Parse) -> None:
    try:
        with open_regular(file) as stream:
            if is_archive(stream):
                return
            stream.seek(0)
            try:  # parsed from bytes: lxml reading a Python stream takes the lock for every chunk
                data = stream.read()
            except OSError as exc:
                raise ModelReadError(file, f"cannot read file: {exc.strerror or exc}") from None
        job.tree = parse_xml_bytes(data, file)
    except BaseException as exc:  # handed to the thread that takes the tree
        job.error = exc


def take_parsed(path: Path | str) -> etree._ElementTree | None:
    """The tree parsed in the background for ``path``, once; None when there is none to take.

    Raises what the parse ended in (:class:`ModelReadError` for an unreadable file)."""
    key = _key(path)
    with _lock:
        job = _started.pop(key, None)
    if job is None or job.thread is None:
        return None
    job.thread.join()
    if job.policy != current_policy():
        return None  # read under other limits: the reader reads it again under the ones in effect
    if job.error is not None:
        raise job.error
    return job.tree


def still_parsing() -> bool:
    """Whether a background parse is under way (imports made now cost no wall time)."""
    with _lock:
        return any(job.thread is not None and job.thread.is_alive() for job in _started.values())

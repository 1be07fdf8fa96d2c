"""The one place that writes generated files: atomically, only inside the output folder,
and only when their content changes.

Every generator (``earl-m2t profile`` today, code generators later) prepares its files as
``{relative path: bytes}`` and hands them to :func:`write_files`:

- every path is checked before anything is written: it must be relative, in POSIX form
  (``src/agent.cpp``), without ``..``, and must stay inside the output folder once
  symbolic links are followed;
- a file whose current bytes equal the new ones is left alone (its modification time is
  kept, so build tools do not rebuild);
- any other file is written to a temporary file in its own folder and moved over the old
  one with :func:`os.replace`, so a reader never sees half a file and an interrupted run
  leaves the previous version in place; the temporary files an interrupted run left beside
  the files being written are removed and reported;
- no file or folder name may exceed 255 bytes (checked with the other paths, so such a
  generation writes nothing); a failure part-way (a full disk) raises :class:`OutputError`
  with what was written before it.

Files given as ``create_only`` (user files of the generation gap) are written only when
no file exists at their path: the new file is linked into place, so an existing file is
never replaced, not even by a race.

Problems raise :class:`OutputError` with a one-line message.
"""

from __future__ import annotations

import os
import re
import stat
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from earl_m2t.shorten import shortened

__all__ = ["OutputError", "WriteReport", "check_relative_path", "write_files"]

_DRIVE = re.compile(r"^[A-Za-z]:")  # a Windows drive ("C:..."): never relative
NAME_MAX = 255  # bytes of one file or folder name: ext4, APFS, NTFS (UTF-16 units) and the rest
# what _write_atomically names its temporary files: "." + the file's name + "." + 8 random characters + ".tmp"
_TEMPORARY = re.compile(r"\.(?P<name>.+)\.[a-z0-9_]{8}\.tmp")


class OutputError(Exception):
    """A generated file cannot be written (bad path, unwritable folder...).

    ``partial`` is what was written before a failure part-way (a full disk, a folder made
    read-only meanwhile); None when nothing was written."""

    def __init__(self, message: str, partial: WriteReport | None = None) -> None:
        super().__init__(message)
        self.partial = partial


@dataclass(frozen=True)
class WriteReport:
    """What :func:`write_files` did: relative paths (POSIX form) in the order processed."""

    out_dir: Path
    written: tuple[str, ...]
    unchanged: tuple[str, ...]
    created: tuple[str, ...] = ()  # create-only files that were missing
    kept: tuple[str, ...] = ()  # create-only files that existed, left as they are
    removed: tuple[str, ...] = ()  # temporary files an interrupted run left, removed

    def lines(self) -> list[str]:
        """One line per file, in path order: ``wrote``, ``unchanged``, ``created`` or ``kept DIR/x``,
        then ``removed DIR/.x.tmp`` for each stale temporary file."""
        status = dict.fromkeys(self.written, "wrote")
        status.update(dict.fromkeys(self.unchanged, "unchanged"))
        status.update(dict.fromkeys(self.created, "created"))
        status.update(dict.fromkeys(self.kept, "kept"))
        return [f"{status[path]} {self.out_dir / path}" for path in sorted(status)] + [
            f"removed {self.out_dir / path} (a temporary file left by an interrupted run)" for path in self.removed]


def check_relative_path(name: str) -> PurePosixPath:
    """The normalised relative path for ``name``; raises OutputError when it could leave
    the output folder or is not a plain relative file path."""
    if not name or "\x00" in name or "\\" in name:
        raise OutputError(f"invalid output path {name!r}")
    path = PurePosixPath(name)
    if path.is_absolute() or _DRIVE.match(name):
        raise OutputError(f"output path {name!r} is absolute; it must be relative to the output folder")
    if ".." in path.parts:
        raise OutputError(f"output path {name!r} leaves the output folder")
    if not path.parts or path == PurePosixPath("."):
        raise OutputError(f"output path {name!r} names no file")
    for part in path.parts:
        size = len(part.encode("utf-8", "surrogateescape"))
        if size > NAME_MAX:
            raise OutputError(f"output path {shortened(name)!r} has a file or folder name of {size} bytes, more than "
                              f"the {NAME_MAX} file systems allow (rule D005 reports such names); nothing written")
    return path


def write_files(out_dir: Path | str, files: Mapping[str, bytes],
                create_only: Mapping[str, bytes] | None = None) -> WriteReport:
    """Write ``files`` (relative path → content) under ``out_dir``, creating folders as needed,
    and each of ``create_only`` when nothing exists at its path yet.

    All paths are validated before the first write. Returns which files were written, which
    were already up to date, which were created and which kept. Raises OutputError.
    """
    root_given = Path(out_dir)
    planned: dict[PurePosixPath, bytes] = {}
    once: set[PurePosixPath] = set()
    for group, mapping in ((False, files), (True, create_only or {})):
        for name, content in mapping.items():
            relative = check_relative_path(name)
            if relative in planned:
                raise OutputError(f"output path {name!r} is given twice")
            planned[relative] = bytes(content)
            if group:
                once.add(relative)

    root = _prepare_root(root_given)
    targets: list[tuple[PurePosixPath, Path, bytes]] = []
    for relative, content in sorted(planned.items()):
        target = root.joinpath(*relative.parts)
        resolved = target.resolve()
        if not resolved.is_relative_to(root):
            raise OutputError(f"output path {str(relative)!r} leads outside {root_given} (through a symbolic link)")
        targets.append((relative, target, content))

    removed = _remove_stale_temporaries(root, [relative for relative, _, _ in targets])
    renamed_in: set[Path] = set()  # folders whose entries changed: synced once each, at the end
    written: list[str] = []
    unchanged: list[str] = []
    created: list[str] = []
    kept: list[str] = []
    for relative, target, content in targets:
        try:
            if relative in once:
                made = _create_once(target, content, root_given / str(relative))
                (created if made else kept).append(str(relative))
                if made:
                    renamed_in.add(target.parent)
                continue
            if _same_content(target, content):
                unchanged.append(str(relative))
                continue
            _write_atomically(target, content, root_given / str(relative))
            renamed_in.add(target.parent)
        except OutputError as error:
            _sync_folders(renamed_in)
            done = WriteReport(root_given, tuple(written), tuple(unchanged), tuple(created), tuple(kept), removed)
            processed = len(written) + len(unchanged) + len(created) + len(kept)
            raise OutputError(f"{error}; {len(written) + len(created)} file(s) were written before it (listed "
                              f"above), {len(targets) - processed} of {len(targets)} were not", done) from None
        written.append(str(relative))
    _sync_folders(renamed_in)
    return WriteReport(root_given, tuple(written), tuple(unchanged), tuple(created), tuple(kept), removed)


def _remove_stale_temporaries(root: Path, relatives: list[PurePosixPath]) -> tuple[str, ...]:
    """Remove the temporary files an interrupted run left beside the files about to be written
    (``.NAME.XXXXXXXX.tmp`` for a planned ``NAME`` in the same folder, regular files only)."""
    planned: dict[PurePosixPath, set[str]] = {}
    for relative in relatives:
        planned.setdefault(relative.parent, set()).add(relative.name)
    removed: list[str] = []
    for folder, names in sorted(planned.items()):
        try:
            entries = sorted(os.listdir(root.joinpath(*folder.parts)))
        except OSError:
            continue  # not there yet: nothing left in it
        for entry in entries:
            match = _TEMPORARY.fullmatch(entry)
            if match is None or match.group("name") not in names:
                continue
            path = root.joinpath(*folder.parts, entry)
            try:
                if stat.S_ISREG(path.lstat().st_mode):
                    path.unlink()
                    removed.append(str(folder / entry))
            except OSError as error:
                raise OutputError(f"cannot remove {path}, a temporary file left by an interrupted run: "
                                  f"{_reason(error)}") from None
    return tuple(removed)


# ---------------------------------------------------------------- internals


def written_by_earl_m2t(path: Path, marker: bytes) -> bool:
    """Whether ``path`` is a regular file (not a link) that starts with ``marker``: how earlier
    output is told apart from the user's own files when it is reported, never to delete it."""
    if path.is_symlink() or not path.is_file():
        return False
    try:
        with path.open("rb") as stream:
            return stream.read(len(marker)) == marker
    except OSError:
        return False


def _prepare_root(root: Path) -> Path:
    try:
        root.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise OutputError(f"cannot write to {root}: it exists and is not a folder") from None
    except OSError as error:
        raise OutputError(f"cannot create output folder {root}: {_reason(error)}") from None
    if not root.is_dir():
        raise OutputError(f"cannot write to {root}: it is not a folder")
    return root.resolve()


def _same_content(target: Path, content: bytes) -> bool:
    try:
        info = target.lstat()
    except FileNotFoundError:
        return False
    except OSError as error:
        raise OutputError(f"cannot read {target}: {_reason(error)}") from None
    if stat.S_ISDIR(info.st_mode):
        raise OutputError(f"cannot write {target}: it is a folder")
    if not stat.S_ISREG(info.st_mode) or info.st_size != len(content):
        return False
    try:
        return target.read_bytes() == content
    except OSError as error:
        raise OutputError(f"cannot read {target}: {_reason(error)}") from None


def _write_atomically(target: Path, content: bytes, shown: Path) -> None:
    folder = target.parent
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputError(f"cannot create folder for {shown}: {_reason(error)}") from None
    mode = _mode_for(target)
    try:
        handle, temporary = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as error:
        raise OutputError(f"cannot write {shown}: {_reason(error)}") from None
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(content)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, mode)
        os.replace(temporary, target)
    except OSError as error:
        try:
            os.unlink(temporary)
        except OSError:
            pass
        raise OutputError(f"cannot write {shown}: {_reason(error)}") from None


def _create_once(target: Path, content: bytes, shown: Path) -> bool:
    """Write ``target`` only if nothing is there (a hard link never replaces); True if created."""
    if os.path.lexists(target):
        return False
    folder = target.parent
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as error:
        raise OutputError(f"cannot write {shown}: {_reason(error)}") from None
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(content)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, _mode_for(target))
        try:
            os.link(temporary, target)
        except FileExistsError:
            return False
        except OSError:  # no hard links here: fall back to an exclusive create
            try:
                with open(target, "xb") as stream:
                    stream.write(content)
            except FileExistsError:
                return False
    except OSError as error:
        raise OutputError(f"cannot write {shown}: {_reason(error)}") from None
    finally:
        try:
            os.unlink(temporary)
        except OSError:
            pass
    return True


def _mode_for(target: Path) -> int:
    """Keep the permissions of the file being replaced; a new file gets the usual ones."""
    try:
        info = target.stat()
        if stat.S_ISREG(info.st_mode):
            return stat.S_IMODE(info.st_mode)
    except OSError:
        pass
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _sync_folders(folders: set[Path]) -> None:
    """Make the renames durable, one fsync per folder (each file's content was synced before its
    rename, so a crash leaves every file either old or new)."""
    for folder in sorted(folders):
        _sync_folder(folder)


def _sync_folder(folder: Path) -> None:
    """Make the renames in ``folder`` durable where the platform allows fsync on a folder."""
    try:
        descriptor = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(descriptor)
    except OSError:
        pass
    finally:
        os.close(descriptor)


def _reason(error: OSError) -> str:
    return error.strerror or str(error)

"""The model members of a MagicDraw / Cameo project archive (``.mdzip``), read in memory.

A ``.mdzip`` is a ZIP archive; its model is the member ``com.nomagic.magicdraw.uml_model.model``
(plus ``…shared_model`` when the project shares content), plain OMG XMI. Every other member
(``proxy.local__*`` internal stubs, ``BINARY-*`` diagram layouts, ``*.properties``, project
options) is ignored. Nothing is extracted to disk, and each member is read in bounded chunks, so
an archive that lies about its sizes (a ZIP bomb) is refused after at most ``MAX_MEMBER_BYTES``.
The member names come from ``[mdzip]`` in ``metamodel/xmi/dialects.toml``.
"""

from __future__ import annotations

import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.dialects import dialect_table

MAX_MEMBER_BYTES = 1 << 30  # 1 GiB of XMI: far above real projects, far below a bomb's payload
MAX_RATIO = 200  # uncompressed / compressed; XMI compresses about 10:1, bombs 1000:1 and more
RATIO_FLOOR = 1 << 20  # members smaller than this are never refused for their ratio
_CHUNK = 1 << 20


@dataclass(frozen=True)
class Member:
    """One model member: the name it is reported under (``x.mdzip!member``) and its bytes."""

    file: str
    data: bytes


def member_file(archive: str, member: str) -> str:
    """How locations in a member are shown: ``project.mdzip!com.nomagic.magicdraw.uml_model.model``."""
    return f"{archive}!{member}"


def is_archive(source: Path | BinaryIO) -> bool:
    """Whether a file (a path, or a seekable stream opened by :mod:`earl_m2t.read.bounded`) is a ZIP archive."""
    try:
        return zipfile.is_zipfile(source)
    except OSError:
        return False


def read_model_members(source: Path | BinaryIO, shown: str | None = None) -> list[Member]:
    """The model members of an ``.mdzip``, first the main model; :class:`ModelReadError` otherwise."""
    file = shown if shown is not None else str(source)
    names = dialect_table().mdzip_members
    try:
        with zipfile.ZipFile(source) as archive:
            present = {info.filename: info for info in archive.infolist()}
            if not names or names[0] not in present:
                raise ModelReadError(
                    file, f"ZIP archive without a MagicDraw model member ({names[0] if names else '?'}): "
                    "not a Cameo/MagicDraw .mdzip project"
                )
            return [_read(archive, present[name], file) for name in names if name in present]
    except ModelReadError:
        raise
    except (zipfile.BadZipFile, zipfile.LargeZipFile, zlib.error, EOFError) as exc:
        raise ModelReadError(file, f"damaged ZIP archive: {_short(exc)}") from None
    except NotImplementedError as exc:  # an unsupported compression method
        raise ModelReadError(file, f"cannot read ZIP archive: {_short(exc)}") from None
    except RuntimeError as exc:  # an encrypted member
        raise ModelReadError(file, f"cannot read ZIP archive: {_short(exc)}") from None
    except OSError as exc:
        raise ModelReadError(file, f"cannot read file: {exc.strerror or exc}") from None


def _read(archive: zipfile.ZipFile, info: zipfile.ZipInfo, file: str) -> Member:
    name = member_file(file, info.filename)
    limit = MAX_MEMBER_BYTES
    if info.file_size > limit:
        raise ModelReadError(name, f"archive member too large ({info.file_size} bytes; the limit is {limit})")
    if info.file_size > RATIO_FLOOR and info.file_size > MAX_RATIO * max(info.compress_size, 1):
        raise ModelReadError(
            name, f"archive member compressed {info.file_size // max(info.compress_size, 1)}:1 "
            f"(more than {MAX_RATIO}:1): refused as a possible ZIP bomb"
        )
    chunks: list[bytes] = []
    total = 0
    with archive.open(info) as stream:
        while True:
            chunk = stream.read(_CHUNK)
            if not chunk:
                break
            total += len(chunk)
            if total > limit or (total > RATIO_FLOOR and total > MAX_RATIO * max(info.compress_size, 1)):
                # the central directory lied about the size: stop before it costs memory
                raise ModelReadError(
                    name, f"archive member expands beyond its declared size ({info.file_size} bytes): "
                    "refused as a possible ZIP bomb"
                )
            chunks.append(chunk)
    return Member(name, b"".join(chunks))


def _short(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return text[:200]

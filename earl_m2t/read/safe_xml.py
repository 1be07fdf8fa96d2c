"""The one hardened XML parser: no entity expansion, no network, no DTD loading."""

from __future__ import annotations

import re
from pathlib import Path
from typing import BinaryIO

from lxml import etree

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.bounded import open_regular


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=True,  # real XMI files exceed libxml2's default depth and text limits
        remove_comments=True,
        remove_pis=True,
        remove_blank_text=True,  # XMI whitespace between elements carries nothing; it costs memory
        collect_ids=False,
    )


def parse_xml_bytes(data: bytes, file: str) -> etree._ElementTree:
    """Parse XML bytes safely; any DTD is refused, since XMI never needs one."""
    refuse_doctype_in_prolog(data[:_PROLOG_BYTES], file)
    try:
        root = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as exc:
        line = exc.position[0] if exc.position else 0
        raise ModelReadError(file, f"not well-formed XML: {_short(exc.msg)}", line) from None
    tree = root.getroottree()
    _refuse_doctype(tree, file)
    return tree


_PROLOG_BYTES = 65536
_DOCTYPE = re.compile(rb"<!DOCTYPE", re.IGNORECASE)
_FIRST_ELEMENT = re.compile(rb"<[A-Za-z_]")


def refuse_doctype_in_prolog(head: bytes, file: str) -> None:
    """XMI never declares a DTD: refuse one before the parser sees it (entity expansion, XXE)."""
    doctype = _DOCTYPE.search(head)
    if doctype is None:
        return
    element = _FIRST_ELEMENT.search(head)
    if element is None or doctype.start() < element.start():
        line = head.count(b"\n", 0, doctype.start()) + 1
        raise ModelReadError(file, "document type declarations (DTD, entities) are not allowed in XMI files", line)


def parse_xml_file(path: Path) -> etree._ElementTree:
    """Parse an XML file safely (the bytes go to lxml, so the declared encoding is honoured).

    Only a regular file within the size limit is read (:mod:`earl_m2t.read.bounded`)."""
    with open_regular(path) as stream:
        return parse_xml_stream(stream, str(path))


def parse_xml_stream(stream: BinaryIO, file: str) -> etree._ElementTree:
    """Parse an open, seekable XML file safely, from its start; ``file`` names it in errors."""
    try:
        stream.seek(0)
        refuse_doctype_in_prolog(stream.read(_PROLOG_BYTES), file)
        stream.seek(0)
        tree = etree.parse(stream, _parser())
    except OSError as exc:
        raise ModelReadError(file, f"cannot read file: {exc.strerror or exc}") from None
    except etree.XMLSyntaxError as exc:
        line = exc.position[0] if exc.position else 0
        raise ModelReadError(file, f"not well-formed XML: {_short(exc.msg)}", line) from None
    _refuse_doctype(tree, file)
    return tree


def _refuse_doctype(tree: etree._ElementTree, file: str) -> None:
    docinfo = tree.docinfo
    if docinfo.doctype or docinfo.internalDTD is not None or docinfo.externalDTD is not None:
        raise ModelReadError(
            file, "document type declarations (DTD, entities) are not allowed in XMI files", 1
        )


def _short(message: str | None) -> str:
    text = (message or "syntax error").strip().splitlines()[0]
    text = re.sub(r", line \d+, column \d+$", "", text)  # the location is reported separately
    return text[:200]

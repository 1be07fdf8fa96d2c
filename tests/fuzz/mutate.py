"""Deterministic mutations of model files: bytes, XML trees, ``.mdzip`` archives and SysML v2 text
(the XMI structure's own mutations are in ``mutate_xmi``, SysML v2 tokens in ``mutate_sysml``,
FABRIC packages in ``mutate_fabric``).

Every mutation draws from the ``random.Random`` it is given, so one (seed, input number) always
gives the same input. The hostile values are the ones broken models are made of: names of tens
of thousands of characters (long capital runs included), control characters, Windows device
names, hrefs to devices, FIFOs and files outside the repository, deep nesting, duplicated ids.
"""

from __future__ import annotations

import copy
import io
import random
import re
import zipfile

from lxml import etree

from earl_m2t.read.safe_xml import parse_xml_bytes
from tests.fuzz.mutate_sysml import mutate_tokens
from tests.fuzz.mutate_xmi import mutate_structure

# files the runner puts beside every input (see runner.prepare_folder)
HOSTILE_HREFS = (
    "../../../../../../dev/zero#_0", "/dev/zero#_0", "pipe.uml#_0", "zero.uml#_0", "loop.uml#_0",
    "../../../../../../etc/passwd#_0", "input.uml#_0", "input.xmi#_x", "missing.uml#_1",
    "file:///dev/zero#_0", "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#Real", "#", "",
    "used.mdzip#_0", "%2e%2e/%2e%2e/etc/passwd#_0",
)


def hostile_names(rng: random.Random) -> str:
    choice = rng.randrange(16)
    length = rng.choice((300, 5000, 30000))
    if choice == 0:
        return "A" * length
    if choice == 1:
        return "Ab" * (length // 2)
    if choice == 2:
        return "x" * length + "/pf"
    if choice == 3:
        return rng.choice(("COM1", "con", "NUL/pf", "LPT9/a", "aux.h", "PRN/ib", "com1/m"))
    if choice == 4:
        return "a\x01b" if rng.random() < 0.5 else "\x7fname\x9f"
    if choice == 5:
        return ""
    if choice == 6:
        return "/" * rng.choice((1, 3, 200))
    if choice == 7:
        return "é" * rng.choice((10, 3000)) + "/a"
    if choice == 8:
        return "../../../../tmp/evil"
    if choice == 9:
        return "a b\tc\nd/pp"
    if choice == 10:
        return "(" * rng.choice((50, 500, 5000)) + "x"
    if choice == 11:
        return "∧∨¬" * rng.choice((1, 2000))
    if choice == 12:
        return "class"
    if choice == 13:
        return "9lives/m"
    if choice == 14:
        return "a" * 255 + "/ve"
    return rng.choice(("'", '"', "<", "&amp;", "]]>", "\\", "${x}", "%s%n", "{{x}}", "*/", "/*"))


_BYTE_TOKENS = (
    b"<", b">", b"/>", b'"', b"'", b"&", b"&amp;", b"&#0;", b"&#x1;", b"]]>", b"<![CDATA[", b"<!--",
    b"<!DOCTYPE x [<!ENTITY a \"b\">]>", b"<?xml version='1.0'?>", b"xmi:id=\"_dup\"", b"\x00", b"\x01",
    b"\xff\xfe", b"\xc3", b"\xe2\x88", b"\n", b" ", b"\t", b"=", b":", b"#", b"/", b"href=\"pipe.uml#_0\"",
)
# an attribute after blank space, its name bounded: a constant amount of work at each position
_ATTRIBUTE = re.compile(rb'(?<=\s)([A-Za-z_:][-A-Za-z0-9_:.]{0,60})="([^"<]{0,200})"')


def mutate_bytes(data: bytes, rng: random.Random) -> bytes:
    """One byte-level change: flip, delete, duplicate or insert, or an attribute value replaced."""
    if not data:
        return rng.choice(_BYTE_TOKENS)
    buffer = bytearray(data)
    kind = rng.randrange(6)
    position = rng.randrange(len(buffer))
    if kind == 0:
        for _ in range(rng.randint(1, 8)):
            buffer[rng.randrange(len(buffer))] ^= 1 << rng.randrange(8)
    elif kind == 1:
        del buffer[position:position + rng.choice((1, 2, 16, 256, 4096))]
    elif kind == 2:
        span = bytes(buffer[position:position + rng.choice((1, 8, 64, 1024))])
        at = rng.randrange(len(buffer) + 1)
        buffer[at:at] = span * rng.choice((1, 2, 50))
    elif kind == 3:
        buffer[position:position] = rng.choice(_BYTE_TOKENS)
    else:
        return _replace_attribute(data, rng)
    return bytes(buffer)


def _replace_attribute(data: bytes, rng: random.Random) -> bytes:
    window = rng.randrange(max(len(data) - 65536, 0) + 1)
    matches = list(_ATTRIBUTE.finditer(data, window, window + 65536))
    if not matches:
        return data + rng.choice(_BYTE_TOKENS)
    match = rng.choice(matches)
    if match.group(1) == b"href" or rng.random() < 0.15:
        value = rng.choice(HOSTILE_HREFS)
    else:
        value = hostile_names(rng)
    escaped = value.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;").encode("utf-8")
    return data[:match.start(2)] + escaped + data[match.end(2):]


def _xml_safe(text: str) -> str:
    return "".join(c if c in "\t\n\r" or (" " <= c <= "\ud7ff") or ("\ue000" <= c <= "\ufffd") else "?" for c in text)


def mutate_tree(data: bytes, rng: random.Random) -> bytes:
    """One change to the XML tree: an element deleted, duplicated, moved or nested deep, an id
    or reference rewired, a name or href made hostile. Unparsable input gets a byte change."""
    try:
        root = parse_xml_bytes(data, "<seed>").getroot()
    except Exception:
        return mutate_bytes(data, rng)
    elements = [el for el in root.iter() if isinstance(el.tag, str)]
    if len(elements) < 2:
        return mutate_bytes(data, rng)
    target = rng.choice(elements[1:])
    parent = target.getparent()
    kind = rng.randrange(10)
    if kind >= 7:  # references, containment cycles, stereotype applications, numbers
        mutate_structure(root, rng)
    elif kind == 0 and parent is not None:
        parent.remove(target)
    elif kind == 1 and parent is not None:
        for _ in range(rng.choice((1, 2, 100))):
            parent.append(_copy(target))
    elif kind == 2:
        other = rng.choice(elements)
        if target not in other.iterancestors() and other is not target and parent is not None:
            parent.remove(target)
            other.append(target)
    elif kind == 3 and parent is not None:
        inner = _copy(target)
        outer = inner
        for _ in range(rng.choice((50, 300, 2500))):
            wrapper = etree.Element(target.tag, {k: v for k, v in target.attrib.items() if "id" not in k})
            wrapper.append(outer)
            outer = wrapper
        parent.append(outer)
    elif kind == 4:
        ids = [v for el in elements for k, v in el.attrib.items() if k.endswith("}id")]
        keys = [k for k in target.attrib if not k.endswith("}id")]
        if ids and keys:
            several = " ".join(rng.sample(ids, min(3, len(ids))))
            target.set(rng.choice(keys), rng.choice(ids) if rng.random() < 0.7 else several)
    elif kind == 5:
        key = rng.choice(("name", "href", "body", "value", "type"))
        value = rng.choice(HOSTILE_HREFS) if key == "href" else hostile_names(rng)
        target.set(key, _xml_safe(value))
    else:
        for key in [k for k in target.attrib if k.endswith("}id")]:
            del target.attrib[key]
    return etree.tostring(root.getroottree(), xml_declaration=True, encoding="UTF-8")


def _copy(el: etree._Element) -> etree._Element:
    return copy.deepcopy(el)  # whatever its depth


_TOKEN = re.compile(r"'(?:[^'\\\n]|\\.)*'|\"(?:[^\"\\\n]|\\.)*\"|/\*.*?\*/|//[^\n]*|\w+|\s+|.", re.DOTALL)
_TEXT_TOKENS = (
    "{", "}", "(", ")", ";", ":", ":>", ":>>", "::", "=", "[", "]", "'", '"', "/*", "*/", "part def ",
    "state ", "transition ", "then ", "if ", "first ", "accept ", "do action ", "entry; ", "port ",
    "attribute ", "calc def ", "action def ", "package ", "import ", "private ", "in ", "out ",
    "language \"EARL\" /* a/mi.x ∧ ¬b/pp */", "'x/pp'()", "metadata e : Exclusive about ",
    "@Priority { priority = 1; }",
    "#Memory ", "AgentType::CE", " :> Agent ", " :> System ", " : InputBuffer ", "\u0000", "\u0007", "\\b", "\\f",
    "\u202e", "\ufeff", "\ud7ff", "0x", "1e999", "-", "∧", "∨", "¬", "…",
)


def mutate_text(data: bytes, rng: random.Random) -> bytes:
    """One change to SysML v2 text: tokens or lines deleted, duplicated or inserted, a name made
    hostile, nesting made deep. Text that is not UTF-8 gets a byte change."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return mutate_bytes(data, rng)
    tokens = _TOKEN.findall(text) or [""]
    kind = rng.randrange(12)
    at = rng.randrange(len(tokens))
    if kind >= 8:  # keywords, operators, brackets, numbers, hostile quoted names, long guards
        tokens = mutate_tokens(tokens, rng)
    elif kind == 0:
        del tokens[at:at + rng.choice((1, 1, 3, 20))]
    elif kind == 1:
        tokens[at:at] = tokens[at:at + rng.choice((1, 5, 40))] * rng.choice((1, 2, 30))
    elif kind == 2:
        tokens.insert(at, rng.choice(_TEXT_TOKENS))
    elif kind == 3:
        names = [i for i, token in enumerate(tokens) if token[:1] == "'" or token[:1].isalpha()]
        if names:
            value = hostile_names(rng).replace("\\", "\\\\").replace("'", "\\'")
            tokens[rng.choice(names)] = f"'{value}'"
    elif kind == 4:
        depth = rng.choice((30, 150, 199, 200, 201, 1000, 20000))
        opener = rng.choice(("package P { ", "part def D { ", "state s { ", "(", "[", "{"))
        closer = {"(": ")", "[": "]"}.get(opener, "} ")
        tokens.insert(at, opener * depth + "x" + closer * depth)
    elif kind == 5:
        lines = text.splitlines(keepends=True) or [""]
        line = rng.randrange(len(lines))
        if rng.random() < 0.5:
            del lines[line]
        else:
            lines.insert(rng.randrange(len(lines) + 1), lines[line])
        return "".join(lines).encode("utf-8")
    elif kind == 6:
        return mutate_bytes(data, rng)
    else:
        other = rng.randrange(len(tokens))
        tokens[at], tokens[other] = tokens[other], tokens[at]
    return "".join(tokens).encode("utf-8", "surrogatepass")


def mutate_archive(data: bytes, rng: random.Random) -> bytes:
    """An ``.mdzip``: its model member mutated as XML (or the archive's bytes, now and then)."""
    if rng.random() < 0.2:
        return mutate_bytes(data, rng)
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as archive:
            members = [(info, archive.read(info)) for info in archive.infolist()]
    except Exception:
        return mutate_bytes(data, rng)
    out = io.BytesIO()
    models = [i for i, (info, _) in enumerate(members) if "model" in info.filename] or [0]
    chosen = rng.choice(models) if members else -1
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for index, (info, content) in enumerate(members):
            if index == chosen:
                content = mutate_tree(content, rng) if rng.random() < 0.6 else mutate_bytes(content, rng)
            archive.writestr(info.filename, content)
    return out.getvalue()


def mutate(data: bytes, suffix: str, rng: random.Random) -> bytes:
    """1 to 4 stacked mutations fitting the file's kind."""
    for _ in range(rng.choice((1, 1, 1, 2, 2, 3, 4))):
        try:
            if suffix == ".sysml":
                data = mutate_text(data, rng)
            elif suffix == ".mdzip":
                data = mutate_archive(data, rng)
            elif rng.random() < 0.5:
                data = mutate_tree(data, rng)
            else:
                data = mutate_bytes(data, rng)
        except Exception:  # a mutation lxml cannot carry out (serialising a tree it made too deep …)
            data = mutate_bytes(data, rng)
    return data

"""Mutations of a FABRIC package (``spec/subsystem.xml`` and ``config/*.xml``, as a mapping of
relative path to bytes): an attribute made a hostile name, a huge or broken number or a deep
condition (``IN_ERROR``, ``CURRENT_BEHAVIOR_OK``, parentheses hundreds deep), an element deleted
or duplicated, a file missing, or the bytes of a file changed. Every choice draws from the
``random.Random`` given."""

from __future__ import annotations

import random
from pathlib import Path

from lxml import etree

from earl_m2t.read.safe_xml import parse_xml_bytes
from tests.fuzz.mutate import _xml_safe, hostile_names, mutate_bytes
from tests.fuzz.mutate_xmi import HOSTILE_NUMBERS

Package = dict[str, bytes]

CONDITION_WORDS = (
    "TRUE", "FALSE", "IN_ERROR", "CURRENT_BEHAVIOR_OK", "not", "and", "or", "(", ")", "st_ok", "cmd_ok",
    "IN_ERROR and not CURRENT_BEHAVIOR_OK", "",
)


def read_package(folder: Path) -> Package:
    """The XML files of a package folder, keyed by their path inside it (``spec/subsystem.xml`` …)."""
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*.xml")) if p.is_file()}


def write_package(package: Package, folder: Path) -> None:
    for name, content in package.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(content)


def package_folders(root: Path) -> list[Path]:
    """Every folder under ``root`` that holds ``spec/subsystem.xml``, sorted."""
    return sorted(p.parent.parent for p in root.rglob("spec/subsystem.xml")) if root.is_dir() else []


def condition(rng: random.Random) -> str:
    kind = rng.randrange(4)
    if kind == 0:
        depth = rng.choice((10, 199, 201, 1000, 20000))
        return "(" * depth + rng.choice(CONDITION_WORDS[:4]) + ")" * depth
    if kind == 1:
        return " and ".join(rng.choice(CONDITION_WORDS[:4]) for _ in range(rng.choice((3, 500, 20000))))
    if kind == 2:
        return "not " * rng.choice((2, 201, 3000)) + "IN_ERROR"
    return " ".join(rng.choice(CONDITION_WORDS) for _ in range(rng.randint(1, 12)))


def _attribute_value(key: str, rng: random.Random) -> str:
    roll = rng.random()
    if key.endswith("cond") or roll < 0.25:
        return condition(rng)
    if roll < 0.55 or any(word in key for word in ("period", "timeout", "size", "latency")):
        return rng.choice(HOSTILE_NUMBERS)
    return _xml_safe(hostile_names(rng))


def mutate_file(data: bytes, rng: random.Random) -> bytes:
    try:
        root = parse_xml_bytes(data, "<fabric>").getroot()
    except Exception:
        return mutate_bytes(data, rng)
    elements = [el for el in root.iter() if isinstance(el.tag, str)]
    target = rng.choice(elements[1:] or elements)
    parent = target.getparent()
    kind = rng.randrange(5)
    if kind <= 1 and target.attrib:
        key = rng.choice(sorted(target.attrib))
        target.set(key, _attribute_value(key, rng))
    elif kind == 2 and parent is not None:
        parent.remove(target)
    elif kind == 3 and parent is not None:
        for _ in range(rng.choice((1, 2, 1000))):
            parent.append(etree.fromstring(etree.tostring(target)))
    else:
        target.set(rng.choice(("name", "alias", "type", "initial", "stop_cond", "err_cond", "min_period",
                               "first_timeout", "side", "running", "latex")), _attribute_value("x", rng))
    return etree.tostring(root.getroottree(), xml_declaration=True, encoding="UTF-8")


def mutate_package(package: Package, rng: random.Random) -> Package:
    """1 to 3 stacked changes of a package; the result is a new mapping."""
    package = dict(package)
    for _ in range(rng.choice((1, 1, 2, 3))):
        names = sorted(package)
        if not names:
            break
        roll = rng.random()
        name = rng.choice(names)
        if roll < 0.05:
            del package[name]
        elif roll < 0.08:
            package[name.replace(".xml", "_copy.xml") if name.startswith("config/") else name] = package[name]
        elif roll < 0.25:
            package[name] = mutate_bytes(package[name], rng)
        else:
            try:
                package[name] = mutate_file(package[name], rng)
            except Exception:  # a tree lxml cannot serialise (too deep …)
                package[name] = mutate_bytes(package[name], rng)
    return package

"""EARL names, and how they become C++ / ROS identifiers and file names (rules D003, D004; generators).

An EARL name is a descriptive part and the abbreviation of its concept: ``manipulatorCommand/ib``,
``motionFinished/pp``. A replicated element's template names its instances with ``K`` at the end
of the descriptive part (``motorControllerK/ve``: ``motorController1/ve`` …). The functions below
are the one place that splits and joins such names.
"""

from __future__ import annotations

import re
import tomllib
import unicodedata
from functools import cache, lru_cache

from earl_m2t.resources import metamodel_path


@cache
def _table() -> dict:
    return tomllib.loads(metamodel_path("tables", "identifiers.toml").read_text(encoding="utf-8"))


@cache
def _windows_reserved_names() -> frozenset[str]:
    return frozenset(word.upper() for word in _table()["windows_reserved"])


# Models repeat their names (every joint controller has its `idle`, `command/ib` …): the pure
# name functions below remember recent answers instead of folding the same text again.
_REMEMBERED = 1 << 16


def split(name: str) -> tuple[str, str | None]:
    """``manipulatorCommand/ib`` → ("manipulatorCommand", "ib"); a name without ``/`` → (name, None).
    The abbreviation follows the last ``/``."""
    descriptive, slash, abbreviation = name.rpartition("/")
    return (descriptive, abbreviation) if slash else (name, None)


def stem(name: str) -> str:
    """The descriptive part of an EARL name: ``manipulatorCommand/ib`` → ``manipulatorCommand``."""
    return name.rpartition("/")[0] if "/" in name else name


def suffix(name: str) -> str:
    """The abbreviation an EARL name ends with: ``manipulatorCommand/ib`` → ``ib``; "" for none."""
    return name.rpartition("/")[2] if "/" in name else ""


PLACEHOLDER = "K"  # where a replicated element's template puts the instance number


def instance_name(template: str, index: int) -> str:
    """``motorControllerK/ve``, 3 → ``motorController3/ve``; without K the index is appended."""
    descriptive, slash, abbreviation = template.rpartition("/") if "/" in template else (template, "", "")
    if descriptive.endswith(PLACEHOLDER):
        descriptive = descriptive[: -len(PLACEHOLDER)]
    return f"{descriptive}{index}{slash}{abbreviation}"


def instance_template(name: str) -> str:
    """The template an instance name belongs to: ``motorControllerState3/ib`` →
    ``motorControllerStateK/ib``; a name without a trailing number is returned as it is."""
    descriptive, slash, abbreviation = name.rpartition("/") if "/" in name else (name, "", "")
    digits = len(descriptive) - len(descriptive.rstrip("0123456789"))
    if digits and digits < len(descriptive):
        return f"{descriptive[:-digits]}{PLACEHOLDER}{slash}{abbreviation}"
    return name


def identifier(name: str) -> str:
    """The identifier generators use: the abbreviation stays, so ``motionFinished/m`` and
    ``motionFinished/pp`` (both in the paper) become ``motionFinished_m`` and ``motionFinished_pp``."""
    descriptive, slash, abbr = name.rpartition("/")
    return f"{descriptive}_{abbr}" if slash else name


@lru_cache(maxsize=_REMEMBERED)
def identifier_problem(name: str) -> str:
    """Why a name cannot become an identifier, or "" when it can."""
    table = _table()
    descriptive = stem(name).strip()
    if not descriptive:
        return "its descriptive part is empty"
    if not re.match(table["pattern"], descriptive):
        return f"'{descriptive}' is not of the form {table['pattern']}"
    ident = identifier(name)
    if "/" in name and not re.match(table["pattern"], ident):
        return f"'{ident}' is not of the form {table['pattern']}"
    if ident in table["cpp_keywords"]:
        return f"'{ident}' is a C++ keyword"
    if ident in table["ros_reserved"]:
        return f"'{ident}' is reserved in ROS messages"
    return ""


@lru_cache(maxsize=_REMEMBERED)
def length_problem(name: str) -> str:
    """Why a name is too long for the generated files (rule D005), or "" when it is not."""
    limit = int(_table()["max_length"])
    length = len(ascii_fold(identifier(name.strip())))
    if length <= limit:
        return ""
    return f"its generated identifier has {length} characters, more than the {limit} every target can use in file names"


def host_problem(host: str) -> str:
    """Why the tag host of an «Agent» cannot name a file and a ROS node (rule D007), or "" when it can."""
    table = _table()
    if not re.fullmatch(table["host_pattern"], host):
        return "a host name is letters, digits, '_' and '-'"
    if len(host) > int(table["max_length"]):
        return f"it has {len(host)} characters, more than {table['max_length']}"
    if host in table["reserved_hosts"]:
        return f"'{host}' is reserved: {host}.launch.py starts every agent"
    return ""


def host_ros_name(host: str) -> str:
    """A host as part of a ROS node name (no '-' there): ``arm-pc`` -> ``arm_pc``. Two hosts with
    one ROS name are one host too many (rule D007)."""
    return host.replace("-", "_")


@lru_cache(maxsize=_REMEMBERED)
def windows_reserved(name: str) -> str:
    """The Windows device name (``COM1``, ``NUL`` …) a name's files would be called, or ""."""
    reserved = _windows_reserved_names()
    for candidate in (sanitised(name), re.sub(r"[^A-Za-z0-9_]", "_", ascii_fold(stem(name.strip()))),
                      field_name(name), message_name(name)):
        if candidate.upper() in reserved:
            return candidate
    return ""


@lru_cache(maxsize=_REMEMBERED)
def sanitised(name: str) -> str:
    """The identifier a generator derives: non-identifier characters become '_'."""
    return re.sub(r"[^A-Za-z0-9_]", "_", identifier(name))


@lru_cache(maxsize=_REMEMBERED)
def collision_key(name: str) -> str:
    """Two names with the same key clash as identifiers or as file names on a case-insensitive disk."""
    return sanitised(name).lower()


@lru_cache(maxsize=_REMEMBERED)
def ascii_fold(text: str) -> str:
    """ASCII of a name: accents dropped (``ü`` → ``u``), other letters ``uXXXX``, the rest ``_``."""
    out = []
    for char in unicodedata.normalize("NFKD", text):
        if char.isascii():
            out.append(char)
        elif unicodedata.combining(char):
            continue
        elif char.isalnum():
            out.append(f"u{ord(char):04x}")
        else:
            out.append("_")
    return "".join(out)


def words(name: str) -> list[str]:
    """The words of a name: ``jointPosSetpoint`` → joint Pos Setpoint, ``XMLParser`` → XML Parser."""
    return list(_words(name))


@lru_cache(maxsize=_REMEMBERED)
def _words(name: str) -> tuple[str, ...]:
    text = ascii_fold(identifier(name.strip()))
    text = _LOWER_UPPER.sub(r"\1 \2", text)
    text = _ACRONYM_END.sub(r"\1 ", text)
    return tuple(w for w in _NOT_ALNUM.split(text) if w)


# Linear in the length of the name: every pattern looks at a fixed number of characters from
# each position (``([A-Z]+)([A-Z][a-z])`` backtracked over long capital runs: quadratic).
_LOWER_UPPER = re.compile(r"([a-z0-9])([A-Z])")
_ACRONYM_END = re.compile(r"([A-Z])(?=[A-Z][a-z])")  # XMLParser → XML Parser
_NOT_ALNUM = re.compile(r"[^A-Za-z0-9]+")


@lru_cache(maxsize=_REMEMBERED)
def message_name(name: str) -> str:
    """``motor state`` → ``MotorState``; a leading digit gets ``M``, an empty name is ``Unnamed``."""
    text = "".join(w[0].upper() + w[1:] for w in _words(name)) or "Unnamed"
    return "M" + text if text[0].isdigit() else text


@lru_cache(maxsize=_REMEMBERED)
def field_name(name: str) -> str:
    """``jointPosSetpoint`` → ``joint_pos_setpoint``; a leading digit gets ``n``."""
    text = "_".join(w.lower() for w in _words(name)) or "unnamed"
    return "n" + text if text[0].isdigit() else text

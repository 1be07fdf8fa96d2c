"""A model repository's earl-m2t configuration: ``earl-m2t.toml`` or ``[tool.earl-m2t]`` in ``pyproject.toml``.

Discovery starts in the current directory and walks up to the repository root (a folder
holding ``.git``) or the filesystem root; in each folder ``earl-m2t.toml`` wins over a
``pyproject.toml`` that has a ``[tool.earl-m2t]`` table (one without it is passed over).
Paths and globs in the file are relative to its folder. See docs/check.md (*Configuration*) for the keys.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from earl_m2t.check.tables import LinkTable, LinkTableError, builtin_permitted_links, parse_link_table
from earl_m2t.diagnostics import ModelReadError, Severity
from earl_m2t.read.bounded import read_regular_bytes

KEYS = ("select", "ignore", "severity", "per-file-ignores", "permitted-links", "rules", "allow-outside")


class ConfigError(Exception):
    """A configuration that cannot be used; ``str()`` is one line naming the file and the key."""

    def __init__(self, file: Path | str, message: str) -> None:
        super().__init__(f"{shown(Path(file))}: error: {message}")


def shown(path: Path) -> str:
    """A path as messages show it: relative to the current directory when inside it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except (ValueError, OSError):
        return str(path)


@dataclass(frozen=True)
class Config:
    file: Path | None = None  # None: no configuration
    select: tuple[str, ...] | None = None
    ignore: tuple[str, ...] = ()
    severity: tuple[tuple[str, Severity], ...] = ()
    per_file_ignores: tuple[tuple[str, tuple[str, ...]], ...] = ()  # (glob, codes)
    permitted_links: LinkTable | None = None
    rules: tuple[Path, ...] = ()
    allow_outside: tuple[Path, ...] = ()  # folders outside a model's repository its hrefs may name
    root: Path = field(default_factory=Path.cwd)  # the folder globs and paths are relative to

    def relative(self, model: Path) -> str | None:
        """``model``'s path relative to the configuration's folder (None when outside it)."""
        try:
            return model.resolve().relative_to(self.root.resolve()).as_posix()
        except ValueError:
            return None


def glob_matches(pattern: str, relative: str) -> bool:
    """``*`` and ``?`` stay inside one folder, ``**/`` spans folders; a pattern without ``/`` matches file names."""
    if "/" not in pattern:
        relative = relative.rpartition("/")[2]
    regex = ""
    index = 0
    while index < len(pattern):
        if pattern.startswith("**/", index):
            regex, index = regex + "(?:.*/)?", index + 3
        elif pattern.startswith("**", index):
            regex, index = regex + ".*", index + 2
        else:
            char = pattern[index]
            regex += "[^/]*" if char == "*" else "[^/]" if char == "?" else re.escape(char)
            index += 1
    return re.fullmatch(regex, relative.removeprefix("./")) is not None


def discover(start: Path) -> Path | None:
    """The configuration file that applies in ``start``, or None."""
    folder = start.resolve()
    while True:
        own = folder / "earl-m2t.toml"
        if own.is_file():
            return own
        pyproject = folder / "pyproject.toml"
        if pyproject.is_file() and "earl-m2t" in _read(pyproject).get("tool", {}):
            return pyproject
        if (folder / ".git").exists() or folder.parent == folder:
            return None
        folder = folder.parent


def _read(file: Path) -> dict[str, Any]:
    try:
        return tomllib.loads(read_regular_bytes(file).decode("utf-8"))
    except ModelReadError as exc:  # a FIFO, a device, a file over the size limit
        raise ConfigError(file, f"cannot be read: {exc.message}") from None
    except OSError as exc:
        raise ConfigError(file, f"cannot be read: {exc.strerror or exc}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ConfigError(file, f"not valid TOML: {exc}") from None
    except RecursionError:  # tomllib descends into nested arrays and inline tables
        raise ConfigError(file, "not read: arrays or inline tables nested too deeply") from None


def _strings(file: Path, key: str, value: object) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(item, str) for item in value):
        raise ConfigError(file, f"'{key}' must be a list of strings")
    return tuple(value)


def load_config(file: Path) -> Config:
    """Read and validate one configuration file (rule codes are checked later, with the rules)."""
    data = _read(file)
    table = data.get("tool", {}).get("earl-m2t") if file.name == "pyproject.toml" else data
    prefix = "tool.earl-m2t." if file.name == "pyproject.toml" else ""
    if not isinstance(table, dict):
        raise ConfigError(file, "has no [tool.earl-m2t] table")
    for key in table:
        if key not in KEYS:
            raise ConfigError(file, f"unknown key '{prefix}{key}' (known: {', '.join(KEYS)})")
    root = file.resolve().parent
    severity: list[tuple[str, Severity]] = []
    severities = table.get("severity", {})
    if not isinstance(severities, dict):
        raise ConfigError(file, f"'{prefix}severity' must be a table of CODE = \"error|warning|info\"")
    for code, level in severities.items():
        try:
            severity.append((code, Severity.parse(str(level))))
        except ValueError:
            raise ConfigError(file, f"'{prefix}severity.{code}' must be error, warning or info, "
                                    f"not {level!r}") from None
    per_file = table.get("per-file-ignores", {})
    if not isinstance(per_file, dict):
        raise ConfigError(file, f"'{prefix}per-file-ignores' must be a table of \"glob\" = [codes]")
    links: LinkTable | None = None
    if "permitted-links" in table:
        links = _links(file, prefix, table["permitted-links"], root)
    rules = tuple(root / rel for rel in _strings(file, prefix + "rules", table.get("rules", [])))
    return Config(
        file=file,
        select=_strings(file, prefix + "select", table["select"]) if "select" in table else None,
        ignore=_strings(file, prefix + "ignore", table.get("ignore", [])),
        severity=tuple(severity),
        per_file_ignores=tuple((glob, _strings(file, f"{prefix}per-file-ignores.{glob}", codes))
                               for glob, codes in per_file.items()),
        permitted_links=links,
        rules=rules,
        allow_outside=tuple(root / rel for rel in
                            _strings(file, prefix + "allow-outside", table.get("allow-outside", []))),
        root=root,
    )


def _links(file: Path, prefix: str, value: object, root: Path) -> LinkTable:
    """``permitted-links``: a table of the shape of permitted-links.toml, or the path of such a file."""
    where: Path | str = file
    key = prefix + "permitted-links"
    if isinstance(value, str):
        where = root / value
        value = _read(where)
        key = "permitted-links"
    if not isinstance(value, dict):
        raise ConfigError(file, f"'{key}' must be a table or the path of a TOML file")
    try:
        return parse_link_table(value, builtin_permitted_links())
    except LinkTableError as exc:
        raise ConfigError(where, f"'{key}': {exc}") from None

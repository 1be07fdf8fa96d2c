"""What ``check``, ``gen`` and ``report`` check a model with: the configuration, then the
command line's ``--select`` and ``--ignore`` over it, with the repository's own rules."""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

from earl_m2t.check.engine import CheckOptions
from earl_m2t.check.registry import select_codes
from earl_m2t.check.user_rules import UserRule, parse_user_rules
from earl_m2t.config import Config, ConfigError, discover, glob_matches, load_config, shown
from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.bounded import ReadPolicy, current_policy, read_regular_bytes


class UsageError(Exception):
    """Bad codes on the command line or in the configuration: one line, exit 2."""


def _codes(text: str) -> list[str]:
    return [item for item in text.replace(" ", ",").split(",") if item]


def expand(selectors: Iterable[str], user_rules: tuple[UserRule, ...], where: str) -> frozenset[str]:
    """Codes for selectors: built-in codes, prefixes and names, or a repository rule's name or prefix (``team.``)."""
    user_codes = {info.code for info, _ in user_rules}
    chosen: set[str] = set()
    for item in selectors:
        try:
            chosen |= select_codes([item])
        except KeyError:
            matches = {c for c in user_codes if c == item or c.startswith(item.rstrip(".") + ".")}
            if not matches:
                raise UsageError(f"{where}unknown rule code or name {item!r} (see earl-m2t rules)") from None
            chosen |= matches
    return frozenset(chosen)


@dataclass(frozen=True)
class Settings:
    """What every file is checked with; ``per_file`` adds ignores by glob."""

    options: CheckOptions
    config: Config = field(default_factory=Config)
    per_file: tuple[tuple[str, frozenset[str]], ...] = ()

    def read_policy(self) -> ReadPolicy:
        """The command line's read policy with the configuration's ``allow-outside`` folders added."""
        given = current_policy()
        return dataclasses.replace(given, allow_outside=given.allow_outside + self.config.allow_outside)

    def options_for(self, model: str) -> CheckOptions:
        relative = self.config.relative(Path(model))
        if relative is None or not self.per_file:
            return self.options
        extra = frozenset().union(*(codes for glob, codes in self.per_file if glob_matches(glob, relative)))
        return dataclasses.replace(self.options, ignore=self.options.ignore | extra) if extra else self.options


def _config(args: argparse.Namespace) -> Config:
    if args.no_config:
        return Config()
    file = args.config if args.config is not None else discover(Path.cwd())
    if file is None:
        return Config()
    if not file.is_file():
        raise ConfigError(file, "no such file")
    return load_config(file)


def settings(args: argparse.Namespace) -> Settings:
    """The options of the run: configuration, then the command line over it (``--select`` and
    ``--ignore`` where the command has them)."""
    config = _config(args)
    select_arg: str | None = getattr(args, "select", None)
    ignore_arg: str | None = getattr(args, "ignore", None)
    where = f"{shown(config.file)}: error: " if config.file else "earl-m2t: "
    user_rules: list[UserRule] = []
    for file in config.rules:
        display = shown(file)
        try:
            text = read_regular_bytes(file).decode("utf-8")
        except ModelReadError as exc:  # missing, a FIFO, a device, over the size limit
            raise ConfigError(config.file or display, f"rule file {display}: {exc.message}") from None
        except UnicodeDecodeError as exc:
            raise ConfigError(config.file or display, f"rule file {display}: not UTF-8 text ({exc.reason})") from None
        user_rules.extend(parse_user_rules(text, display))
    rules = tuple(user_rules)
    if select_arg is not None:
        select = expand(_codes(select_arg), rules, "earl-m2t: ") if select_arg else None
    else:
        select = expand(config.select, rules, f"{where}'select': ") if config.select is not None else None
    if ignore_arg is not None:
        ignore = expand(_codes(ignore_arg), rules, "earl-m2t: ")
    else:
        ignore = expand(config.ignore, rules, f"{where}'ignore': ")
    severities = tuple((code, level) for selector, level in config.severity
                       for code in sorted(expand([selector], rules, f"{where}'severity': ")))
    per_file = tuple((glob, expand(codes, rules, f"{where}'per-file-ignores': ")) for glob, codes in
                     config.per_file_ignores)
    options = CheckOptions(select=select, ignore=ignore, severities=severities,
                           permitted_links=config.permitted_links, extra_rules=rules)
    return Settings(options, config, per_file)


def options_for_model(args: argparse.Namespace, model: str) -> tuple[CheckOptions, ReadPolicy]:
    """The options one model is checked with by ``gen`` and ``report``, and the read policy it is
    read with. Raises ConfigError, UsageError or SourceTextError (one line each)."""
    setup = settings(args)
    return setup.options_for(model), setup.read_policy()

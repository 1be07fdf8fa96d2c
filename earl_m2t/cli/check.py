"""``earl-m2t check PATH...``: run the EARL rules over model files and folders, exit 1 on errors.

The configuration (:mod:`earl_m2t.config`) and the repository's own rules are read first; a
problem with either is one line on stderr and exit 2, before any model is read. Files are
checked one after the other, or by ``--jobs N`` worker processes; the output is the same.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from earl_m2t.api import check_loaded, load
from earl_m2t.check.engine import CheckOptions
from earl_m2t.check.registry import catalogue, select_codes
from earl_m2t.check.user_rules import UserRule, parse_user_rules
from earl_m2t.cli.config_option import add_config_options
from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.profile_files_option import add_profile_files_option
from earl_m2t.cli.discover import model_files
from earl_m2t.cli.progress import Progress
from earl_m2t.cli.read_options import add_read_options
from earl_m2t.config import Config, ConfigError, discover, glob_matches, load_config, shown
from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity, SourceTextError
from earl_m2t.read.bounded import ReadPolicy, current_policy, read_regular_bytes, reading_with
from earl_m2t.render.diagnostics import FORMATS, CheckReport


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("check", help="check models against the EARL rules")
    parser.add_argument("models", nargs="+", metavar="PATH",
                        help="model files (XMI, .mdzip) or folders to search for them")
    parser.add_argument("--format", choices=sorted(FORMATS), default="text")
    parser.add_argument("--select", default=None, metavar="CODES",
                        help="comma-separated codes, prefixes (S, B00) or rule names to run (default: all); "
                             "replaces the configuration's")
    parser.add_argument("--ignore", default=None, metavar="CODES",
                        help="comma-separated codes or prefixes to skip; replaces the configuration's")
    add_config_options(parser)
    parser.add_argument("--jobs", "-j", type=int, default=1, metavar="N", help="check N files at a time")
    add_dialect_option(parser)
    add_profile_files_option(parser)
    add_read_options(parser)
    parser.set_defaults(run=run)


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


@dataclass(frozen=True)
class Outcome:
    """One file's result, as a worker process sends it back."""

    file: str
    diagnostics: list[Diagnostic]
    error: str = ""  # the one line of an unreadable file
    unreadable: dict[str, object] | None = None


def options_for_model(args: argparse.Namespace, model: str) -> tuple[CheckOptions, ReadPolicy]:
    """The options one model is checked with by ``gen`` and ``report``, and the read policy it is
    read with. Raises ConfigError, UsageError or SourceTextError (one line each)."""
    setup = settings(args)
    return setup.options_for(model), setup.read_policy()


def check_file(file: str, options: CheckOptions, dialect: str | None, policy: ReadPolicy,
               profiles: tuple[str, ...] = ()) -> Outcome:
    try:
        with reading_with(policy):
            return Outcome(file, check_loaded(load(file, dialect, profiles), options))
    except ModelReadError as exc:
        return Outcome(file, [], exc.one_line(), {"file": exc.file, "line": exc.line, "message": exc.message})


def _run_all(files: list[str], setup: Settings, dialect: str | None, jobs: int,
             profiles: tuple[str, ...] = ()) -> list[Outcome]:
    progress = Progress(len(files), sys.stderr)
    results: dict[str, Outcome] = {}
    try:
        if jobs <= 1 or len(files) <= 1:
            for index, file in enumerate(files, 1):
                progress.show(index, file)
                results[file] = check_file(file, setup.options_for(file), dialect, setup.read_policy(), profiles)
        else:
            with ProcessPoolExecutor(max_workers=min(jobs, len(files))) as pool:
                futures = {pool.submit(check_file, f, setup.options_for(f), dialect, setup.read_policy(),
                                       profiles): f for f in files}
                for done, future in enumerate(as_completed(futures), 1):
                    progress.show(done, futures[future])
                    results[futures[future]] = future.result()
    finally:
        progress.clear()
    return [results[file] for file in files]


def run(args: argparse.Namespace) -> int:
    if args.jobs < 1:
        print("earl-m2t: --jobs must be at least 1", file=sys.stderr)
        return 2
    try:
        setup = settings(args)
    except (ConfigError, UsageError, SourceTextError) as exc:
        print(str(exc).splitlines()[0], file=sys.stderr)
        return 2
    files, empty = model_files(args.models)
    for folder in empty:
        print(f"{folder}: warning: no model files found", file=sys.stderr)
    outcomes = _run_all(files, setup, args.dialect, args.jobs, tuple(args.profiles))
    diagnostics = sorted((d for o in outcomes for d in o.diagnostics), key=Diagnostic.sort_key)
    for outcome in outcomes:
        if outcome.error:
            print(outcome.error, file=sys.stderr)
    checked = [o.file for o in outcomes if not o.error]
    unreadable = [o.unreadable for o in outcomes if o.unreadable is not None]
    options = setup.options
    ran = [c for c in catalogue() if options.enabled(c)] + [
        info.code for info, _ in options.extra_rules if options.enabled(info.code)]
    sys.stdout.write(FORMATS[args.format](CheckReport(diagnostics, checked, unreadable, rules=ran)))
    if unreadable:
        return 2
    return 1 if any(d.severity is Severity.ERROR for d in diagnostics) else 0

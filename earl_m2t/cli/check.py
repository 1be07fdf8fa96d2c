"""``earl-m2t check MODEL...``: run the EARL rules, print diagnostics, exit 1 on errors."""

from __future__ import annotations

import argparse
import sys

from earl_m2t.api import check_loaded, load
from earl_m2t.check.engine import CheckOptions
from earl_m2t.check.registry import select_codes
from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity
from earl_m2t.render.diagnostics import FORMATS, CheckReport


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("check", help="check models against the EARL rules")
    parser.add_argument("models", nargs="+", metavar="MODEL", help="model files (XMI)")
    parser.add_argument("--format", choices=sorted(FORMATS), default="text")
    parser.add_argument("--select", default="", metavar="CODES",
                        help="comma-separated codes, prefixes (S, B00) or rule names to run (default: all)")
    parser.add_argument("--ignore", default="", metavar="CODES", help="comma-separated codes or prefixes to skip")
    add_dialect_option(parser)
    parser.set_defaults(run=run)


def _codes(text: str) -> list[str]:
    return [item for item in text.replace(" ", ",").split(",") if item]


def run(args: argparse.Namespace) -> int:
    try:
        select = frozenset(select_codes(_codes(args.select))) if args.select else None
        ignore = frozenset(select_codes(_codes(args.ignore)))
    except KeyError as exc:
        print(f"earl-m2t: unknown rule code or name {exc.args[0]!r} (see earl-m2t rules)", file=sys.stderr)
        return 2
    options = CheckOptions(select=select, ignore=ignore)
    diagnostics: list[Diagnostic] = []
    checked: list[str] = []
    unreadable: list[dict[str, object]] = []
    for model in args.models:
        try:
            diagnostics.extend(check_loaded(load(model, args.dialect), options))
            checked.append(model)
        except ModelReadError as exc:
            print(exc.one_line(), file=sys.stderr)
            unreadable.append({"file": exc.file, "line": exc.line, "message": exc.message})
    sys.stdout.write(FORMATS[args.format](CheckReport(diagnostics, checked, unreadable)))
    if unreadable:
        return 2
    return 1 if any(d.severity is Severity.ERROR for d in diagnostics) else 0

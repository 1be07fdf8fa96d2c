"""``earl-m2t gen MODEL --target NAME -o DIR``: generate a target's files from a model.

The model is checked first: error-severity findings are printed and nothing is generated
(exit 1) unless ``--force``. Prints one line per file: ``wrote``/``unchanged`` for generated
files, ``created``/``kept`` for user files (never overwritten), and ``orphaned`` for user
files the model no longer produces (kept). An unreadable model or an unwritable folder is
one line on stderr, exit 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from earl_m2t.cli.config_option import add_config_options
from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.early_parse import parses_model_early
from earl_m2t.cli.profile_files_option import add_profile_files_option
from earl_m2t.cli.read_options import add_read_options
from earl_m2t.gen_targets import gen_targets


def add_parser(commands: argparse._SubParsersAction) -> None:
    targets = gen_targets()
    parser = commands.add_parser("gen", help="generate code, messages, packages or documents from a model",
                                 description="Generate a target's files from an EARL model.")
    parser.add_argument("model", metavar="MODEL", help="the model file")
    parser.add_argument("--target", default=targets[0].name, choices=[t.name for t in targets],
                        help="what to generate: " + "; ".join(f"{t.name}: {t.help} ({t.doc})" for t in targets)
                             + f"; default {targets[0].name}")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created when missing)")
    parser.add_argument("--templates", type=Path, default=None, metavar="DIR",
                        help="a folder of templates searched before the built-in ones")
    parser.add_argument("--force", action="store_true",
                        help="generate even when the model has error findings")
    add_config_options(parser)
    add_dialect_option(parser)
    add_profile_files_option(parser)
    add_read_options(parser)
    parser.set_defaults(run=run)


@parses_model_early
def run(args: argparse.Namespace) -> int:
    from earl_m2t.cli.checked_model import read_and_check
    from earl_m2t.diagnostics import Severity
    from earl_m2t.gen import GenError, generate
    from earl_m2t.output import OutputError
    from earl_m2t.render.diagnostics import text_line
    from earl_m2t.shorten import shortened_words

    checked = read_and_check(args, "gen")
    if isinstance(checked, int):
        return checked
    loaded = checked.loaded
    errors = [d for d in checked.findings if d.severity == Severity.ERROR]
    if errors and not args.force:
        for diagnostic in errors:
            print(text_line(diagnostic), file=sys.stderr)
        print(f"earl-m2t: gen: {len(errors)} error(s) in {args.model}; nothing generated (--force to generate anyway)",
              file=sys.stderr)
        return 1
    try:
        report = generate(loaded.model, args.output, args.target, args.templates, strict=not args.force)
    except GenError as error:
        print(shortened_words(f"earl-m2t: gen: {error}"), file=sys.stderr)
        return 1
    except OutputError as error:
        for line in error.partial.lines() if error.partial is not None else ():
            print(line)  # what was written before the failure
        print(shortened_words(f"earl-m2t: gen: {error}"), file=sys.stderr)
        return 2
    for line in report.lines():
        print(line)
    return 0


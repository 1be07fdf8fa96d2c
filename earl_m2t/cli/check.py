"""``earl-m2t check PATH...``: run the EARL rules over model files and folders, exit 1 on errors.

The configuration (:mod:`earl_m2t.config`) and the repository's own rules are read first; a
problem with either is one line on stderr and exit 2, before any model is read. Files are
checked one after the other, or by ``--jobs N`` worker processes; the output is the same
(:mod:`earl_m2t.cli.check_files`).
"""

from __future__ import annotations

import argparse

from earl_m2t.cli.config_option import add_config_options
from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.profile_files_option import add_profile_files_option
from earl_m2t.cli.read_options import add_read_options

# The keys of earl_m2t.render.diagnostics.FORMATS, named here so that the parser is built
# without importing the renderers (a test keeps the two equal).
OUTPUT_FORMATS = ("github", "json", "junit", "sarif", "text")


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("check", help="check models against the EARL rules")
    parser.add_argument("models", nargs="+", metavar="PATH",
                        help="model files (XMI, .mdzip) or folders to search for them")
    parser.add_argument("--format", choices=OUTPUT_FORMATS, default="text")
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


def run(args: argparse.Namespace) -> int:
    from earl_m2t.read.early import parsing_early

    # one model file: it parses while the checker is imported (earl_m2t.read.early)
    with parsing_early(args.models[0] if len(args.models) == 1 else None):
        from earl_m2t.cli.check_files import run_check

        return run_check(args)

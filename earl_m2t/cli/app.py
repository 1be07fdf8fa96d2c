"""The ``earl-m2t`` command line: argument parsing, dispatch, exit codes.

Exit codes: 0 success (no error-severity finding), 1 error findings, 2 bad usage or a model
that cannot be read, 3 an internal error (reported in one line, never as a traceback).
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
from collections.abc import Sequence
from typing import NoReturn

from earl_m2t.cli import check as check_command
from earl_m2t.cli import convert as convert_command
from earl_m2t.cli import diff as diff_command
from earl_m2t.cli import gen as gen_command
from earl_m2t.cli import import_fabric as import_command
from earl_m2t.cli import profile as profile_command
from earl_m2t.cli import report as report_command
from earl_m2t.cli import rules as rules_command
from earl_m2t.cli import show as show_command
from earl_m2t.cli import stats as stats_command
from earl_m2t.cli import trace as trace_command
from earl_m2t.cli import verify as verify_command
from earl_m2t.version import __version__

EXIT_OK, EXIT_FINDINGS, EXIT_USAGE, EXIT_INTERNAL = 0, 1, 2, 3


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # one line and exit 2, as for unreadable models
        self.exit(EXIT_USAGE, f"earl-m2t: {message} (see earl-m2t --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="earl-m2t", description="Read, check and generate code from EARL models in SysML.")
    parser.add_argument("--version", action="version", version=f"earl-m2t {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    check_command.add_parser(commands)
    show_command.add_parser(commands)
    rules_command.add_parser(commands)
    stats_command.add_parser(commands)
    profile_command.add_parser(commands)
    gen_command.add_parser(commands)
    report_command.add_parser(commands)
    convert_command.add_parser(commands)
    diff_command.add_parser(commands)
    trace_command.add_parser(commands)
    import_command.add_parser(commands)
    verify_command.add_parser(commands)
    return parser


def entry() -> None:
    """The console script: run, flush, and leave without tearing the model down object by object.

    A large model is a tree of millions of objects; freeing them one by one at exit costs as
    much as parsing them, and the process is ending anyway. Likewise the cyclic garbage
    collector is paused while the model is built: it finds nothing to free there.
    """
    gc.disable()
    code = main()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except BrokenPipeError:
        pass
    os._exit(code)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not args.command:
        parser.print_help(sys.stderr)
        return EXIT_USAGE
    from earl_m2t.cli.read_options import read_policy
    from earl_m2t.deep_stack import call_with_deep_stack
    from earl_m2t.read.bounded import reading_with
    from earl_m2t.shorten import shortened_words

    try:
        with reading_with(read_policy(args)):
            return call_with_deep_stack(lambda: int(args.run(args)))
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        return EXIT_OK
    except Exception as exc:  # a bug in earl-m2t: still one line, never a traceback
        line = shortened_words(f"earl-m2t: internal error: {type(exc).__name__}: {exc}").splitlines()[0]
        print(line, file=sys.stderr)
        return EXIT_INTERNAL

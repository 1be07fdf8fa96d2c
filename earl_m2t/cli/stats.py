"""``earl-m2t stats MODEL``: a generic SysML summary of any model file (placeholder)."""

from __future__ import annotations

import argparse


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("stats", help="count the SysML elements of a model (not implemented yet)")
    parser.add_argument("model", metavar="MODEL")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    print("earl-m2t: stats is not implemented yet")
    return 2

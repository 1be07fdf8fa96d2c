"""``earl-m2t profile --format papyrus|cameo|ea -o DIR``: the EARL profile for a SysML tool (placeholder)."""

from __future__ import annotations

import argparse


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("profile", help="write the EARL profile for a SysML tool (not implemented yet)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    print("earl-m2t: profile is not implemented yet")
    return 2

"""The ``--dialect NAME`` option shared by ``check``, ``show`` and ``stats``: override dialect detection."""

from __future__ import annotations

import argparse

from earl_m2t.read.dialects import dialect_table


def add_dialect_option(parser: argparse.ArgumentParser) -> None:
    names = dialect_table().names
    parser.add_argument(
        "--dialect", choices=names, default=None, metavar="NAME",
        help=f"read the model as this XMI dialect instead of detecting it ({', '.join(names)})",
    )

"""``--allow-outside DIR``: a folder outside the model's repository whose files the model's hrefs may name.

Every command that reads models has it; the configuration's ``allow-outside`` (paths relative
to its folder) adds to it where a command reads the configuration.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from earl_m2t.read.bounded import ReadPolicy


def add_read_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--allow-outside", type=Path, action="append", default=[], metavar="DIR",
                        help="also read files the model references under DIR (default: only inside the "
                             "git work tree holding the model, else its folder); may be repeated")


def read_policy(args: argparse.Namespace) -> ReadPolicy:
    from earl_m2t.read.bounded import ReadPolicy

    return ReadPolicy(allow_outside=tuple(getattr(args, "allow_outside", None) or ()))

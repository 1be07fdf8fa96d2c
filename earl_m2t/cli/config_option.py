"""``--config FILE`` / ``--no-config``: the configuration a command checks models with.

``check`` uses it, and so do ``gen`` (which refuses a model with error findings) and
``report`` (which lists the findings), so that all three see the same findings for the
same repository."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_config_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--config", type=Path, default=None, metavar="FILE",
                        help="earl-m2t.toml or pyproject.toml to use instead of the one found from here upwards")
    parser.add_argument("--no-config", action="store_true", help="use no configuration file")

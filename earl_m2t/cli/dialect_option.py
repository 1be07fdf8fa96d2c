"""The ``--dialect NAME`` option shared by ``check``, ``show`` and ``stats``: override dialect detection."""

from __future__ import annotations

import argparse
import tomllib
from functools import cache

from earl_m2t.resources import metamodel_path


@cache
def dialect_names() -> tuple[str, ...]:
    """The dialects of ``metamodel/xmi/dialects.toml``, read without the XMI reader (and lxml)."""
    data = tomllib.loads(metamodel_path("xmi", "dialects.toml").read_text(encoding="utf-8"))
    return tuple(data["dialects"])


def add_dialect_option(parser: argparse.ArgumentParser) -> None:
    names = dialect_names()
    parser.add_argument(
        "--dialect", choices=names, default=None, metavar="NAME",
        help=f"read the model as this XMI dialect instead of detecting it ({', '.join(names)})",
    )

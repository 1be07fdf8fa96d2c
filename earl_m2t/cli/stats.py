"""``earl-m2t stats MODEL``: a generic SysML summary of any model file, EARL or not."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.read_options import add_read_options

if TYPE_CHECKING:
    from earl_m2t.stats import Stats

FORMAT_VERSION = 1

_LABELS = {
    "blocks": "blocks",
    "parts": "parts",
    "ports": "ports",
    "connectors": "connectors",
    "state_machines": "state machines",
    "transitions": "transitions",
    "activities": "activities",
    "requirements": "requirements",
    "value_types": "value types",
    "data_types": "data types",
    "packages": "packages",
}


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("stats", help="count the SysML elements of a model file (any model, EARL or not)")
    parser.add_argument("model", metavar="MODEL")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    add_dialect_option(parser)
    add_read_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    import json

    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.lift import lift
    from earl_m2t.read.loader import load_raw_model
    from earl_m2t.stats import model_stats
    from earl_m2t.sysml2.files import is_sysml2

    path = Path(args.model)
    if is_sysml2(path):
        print(f"{path}: error: stats counts the elements of SysML v1 XMI; SysML v2 text is not counted "
              "(earl-m2t show reads it)", file=sys.stderr)
        return 2
    try:
        raw = load_raw_model(path, args.dialect)
        size = path.stat().st_size
    except ModelReadError as exc:
        print(exc.one_line(), file=sys.stderr)
        return 2
    earl = lift(raw).model  # the same read serves the counts and the EARL figures
    stats = model_stats(raw, file_size=size, earl=earl)
    if args.format == "json":
        sys.stdout.write(json.dumps(stats_to_dict(stats), indent=2, ensure_ascii=False) + "\n")
    else:
        sys.stdout.write(render_stats(stats))
    return 0


def stats_to_dict(stats: Stats) -> dict[str, Any]:
    """The JSON document; its keys are documented in docs/show-and-stats.md and kept stable."""
    earl = stats.earl
    return {
        "format": FORMAT_VERSION,
        "file": stats.file,
        "dialect": stats.dialect,
        "file_size": stats.file_size,
        "elements": stats.elements,
        "counts": stats.counts(),
        "stereotype_applications": stats.stereotype_applications(),
        "earl": None if earl is None else {"agents": earl.agents, "subsystems": earl.subsystems, "links": earl.links},
    }


def render_stats(stats: Stats) -> str:
    """An aligned two-column table, one figure a line."""
    rows: list[tuple[str, str]] = [
        ("file", stats.file),
        ("dialect", stats.dialect),
        ("file size (bytes)", "" if stats.file_size is None else str(stats.file_size)),
        ("elements with xmi:id", str(stats.elements)),
    ]
    rows += [(_LABELS[key], str(value)) for key, value in stats.counts().items()]
    rows += [(f"stereotype applications: {family}", str(value))
             for family, value in stats.stereotype_applications().items()]
    if stats.earl is None:
        rows.append(("EARL model", "no"))
    else:
        rows += [
            ("EARL model", "yes"),
            ("EARL agents", str(stats.earl.agents)),
            ("EARL subsystems", str(stats.earl.subsystems)),
            ("EARL links", str(stats.earl.links)),
        ]
    width = max(len(label) for label, _ in rows)
    return "".join(f"{label.ljust(width)}  {value}\n" for label, value in rows)

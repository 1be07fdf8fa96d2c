"""``earl-m2t show MODEL``: print the lifted EARL model (outline or JSON)."""

from __future__ import annotations

import argparse
import sys

from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.early_parse import parses_model_early
from earl_m2t.cli.profile_files_option import add_profile_files_option
from earl_m2t.cli.read_options import add_read_options


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("show", help="print the EARL model lifted from a model file")
    parser.add_argument("model", metavar="MODEL")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    add_dialect_option(parser)
    add_profile_files_option(parser)
    add_read_options(parser)
    parser.set_defaults(run=run)


@parses_model_early
def run(args: argparse.Namespace) -> int:
    import json

    from earl_m2t.api import load
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.export import model_to_dict
    from earl_m2t.render.show_text import render_model

    try:
        loaded = load(args.model, args.dialect, args.profiles)
    except ModelReadError as exc:
        print(exc.one_line(), file=sys.stderr)
        return 2
    if args.format == "json":
        document = model_to_dict(loaded.model)
        document["ltl_properties"] = [{"name": p.title, "formula": p.text, "file": p.location.file,
                                       "line": p.location.line} for p in loaded.properties]
        sys.stdout.write(json.dumps(document, indent=2, ensure_ascii=False) + "\n")
    else:
        sys.stdout.write(render_model(loaded.model))
    return 0

"""``earl-m2t convert MODEL --to sysml [-o FILE]``: a model (any supported input) as SysML v2 text.

Writes to stdout, or to FILE atomically (through :mod:`earl_m2t.output`); an existing FILE
with other content (hand edits, say) is kept unless ``--force``, exit 1. A model that cannot
be read, or a file that cannot be written, is one line on stderr and exit 2. So is a model the
text cannot carry: the text is read back before it is written, and must lift to the same EARL
model (:mod:`earl_m2t.diff.round_trip`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.profile_files_option import add_profile_files_option
from earl_m2t.cli.read_options import add_read_options

FORMATS = ("sysml",)


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser(
        "convert",
        help="write the EARL content of a model as SysML v2 text",
        description="Convert a model (SysML v1 XMI of any supported dialect, or SysML v2 text) to SysML v2 text.",
    )
    parser.add_argument("model", metavar="MODEL")
    parser.add_argument("--to", required=True, choices=FORMATS, help="sysml: SysML v2 textual notation")
    parser.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    parser.add_argument("--force", action="store_true",
                        help="replace FILE when it exists with other content (it may hold edits)")
    add_dialect_option(parser)
    add_profile_files_option(parser)
    add_read_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from earl_m2t.api import load
    from earl_m2t.cli.model_file import write_model_file
    from earl_m2t.convert import to_sysml
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.diff.round_trip import NotARoundTrip, check_round_trip

    try:
        loaded = load(args.model, args.dialect, args.profiles)
    except ModelReadError as exc:
        print(exc.one_line(), file=sys.stderr)
        return 2
    text = to_sysml(loaded.model)
    try:
        check_round_trip(loaded.model, text)
    except NotARoundTrip as refused:
        print(f"earl-m2t: convert: {args.model}: {refused}; nothing written", file=sys.stderr)
        return 2
    if not args.output:
        sys.stdout.write(text)
        return 0
    target = Path(args.output)
    content = text.encode("utf-8")
    return write_model_file("convert", target, content, args.force, "conversion")

"""``earl-m2t report MODEL -o DIR``: a static HTML specification of a model.

Writes ``DIR/index.html`` (tables after the EARL paper, the findings of the check, every
element with an id) and ``DIR/diagrams/`` (Graphviz sources and SVG, PNG with ``--png``),
through :mod:`earl_m2t.output`. The report is written whatever the findings; the exit code
is 0 when it was written, 1 when the diagrams cannot be made (``dot`` missing or warning),
2 for an unreadable model or an unwritable folder. See docs/diagrams-and-report.md.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from earl_m2t.cli.config_option import add_config_options
from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.early_parse import parses_model_early
from earl_m2t.cli.profile_files_option import add_profile_files_option
from earl_m2t.cli.read_options import add_read_options


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("report", help="write a static HTML specification of a model",
                                 description="Write an HTML specification of an EARL model: diagrams, the "
                                             "paper-style tables and the findings of the check.")
    parser.add_argument("model", metavar="MODEL", help="the model file")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created when missing)")
    parser.add_argument("--png", action="store_true", help="also write a PNG of every diagram")
    parser.add_argument("--templates", type=Path, default=None, metavar="DIR",
                        help="a folder of report templates searched before the built-in ones")
    parser.add_argument("--verify", action="store_true",
                        help="also model-check the system with SPIN (as earl-m2t verify, with the model's LTL "
                             "properties) and show counterexamples as sequence diagrams")
    add_config_options(parser)
    add_dialect_option(parser)
    add_profile_files_option(parser)
    add_read_options(parser)
    parser.set_defaults(run=run)


@parses_model_early
def run(args: argparse.Namespace) -> int:
    from earl_m2t.cli.checked_model import read_and_check
    from earl_m2t.gen.errors import GenError
    from earl_m2t.gen.orphans import find_stale_diagrams
    from earl_m2t.output import OutputError, write_files
    from earl_m2t.report.page import diagram_folder, render_report
    from earl_m2t.shorten import shortened_words

    checked = read_and_check(args, "report")
    if isinstance(checked, int):
        return checked
    loaded, findings = checked.loaded, checked.findings
    verification = None
    if args.verify:
        from earl_m2t.verify.ltl import LtlError, tokens
        from earl_m2t.verify.run import VerifyOptions, verify_model
        from earl_m2t.verify.spin import SpinUnavailable

        try:
            for prop in loaded.properties:
                tokens(prop, loaded.model)
            verification = verify_model(loaded.model, VerifyOptions(properties=loaded.properties))
        except (LtlError, SpinUnavailable) as error:
            print(f"earl-m2t: report: {error}", file=sys.stderr)
            return 2
    try:
        files = render_report(loaded.model, findings, png=args.png, templates=args.templates,
                              verification=verification)
        written = write_files(args.output, files)
    except GenError as error:
        print(shortened_words(f"earl-m2t: report: {error}"), file=sys.stderr)
        return 1
    except OutputError as error:
        for line in error.partial.lines() if error.partial is not None else ():
            print(line)  # what was written before the failure
        print(shortened_words(f"earl-m2t: report: {error}"), file=sys.stderr)
        return 2
    index = Path(args.output) / "index.html"
    print(f"report {index}: {len(written.written)} file(s) written, {len(written.unchanged)} unchanged")
    for line in written.lines():
        if line.startswith("removed "):
            print(line)
    for stale in find_stale_diagrams(Path(args.output), set(files), diagram_folder()):
        print(f"orphaned {Path(args.output) / stale} (kept; nothing in the model generates it any more)")
    return 0

"""``earl-m2t import fabric PACKAGE_DIR... -o MODEL.sysml``: FABRIC packages as an EARL model.

Each PACKAGE_DIR holds ``spec/subsystem.xml`` and, optionally, ``config/*.xml``. The model is
written as SysML v2 text by the writer of ``earl-m2t convert`` (atomically; an existing file
with other content is kept unless ``--force``, exit 1). A package FABRIC would refuse is one line
``FILE:LINE: error: …`` on stderr and exit 2. See docs/fabric-import.md.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from earl_m2t.sysml2.files import SUFFIX, is_sysml2


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("import", help="read models of other tools into an EARL model",
                                 description="Read models of other tools into an EARL model.")
    kinds = parser.add_subparsers(dest="kind", metavar="KIND", parser_class=type(parser))
    kinds.required = True
    fabric = kinds.add_parser(
        "fabric", help="FABRIC packages (spec/subsystem.xml, config/*.xml) as SysML v2 text",
        description="Read FABRIC packages (spec/subsystem.xml and config/*.xml) into one EARL model, "
                    "written as SysML v2 text.")
    fabric.add_argument("packages", nargs="+", metavar="PACKAGE_DIR")
    fabric.add_argument("-o", "--output", required=True, metavar="MODEL.sysml",
                        help="the model to write (SysML v2 text)")
    fabric.add_argument("--name", help="the model's name (default: the output file's name)")
    fabric.add_argument("--force", action="store_true",
                        help="replace MODEL when it exists with other content (it may hold edits)")
    fabric.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from earl_m2t.cli.model_file import write_model_file
    from earl_m2t.convert import to_sysml
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.fabric import packages_to_model, read_package
    from earl_m2t.gen.names import cpp_identifier
    from earl_m2t.sysml2.limits import size_problem

    target = Path(args.output)
    if not is_sysml2(target):
        print(f"earl-m2t: import fabric: {target}: the model is written as SysML v2 text, name it *{SUFFIX} "
              "(earl-m2t has no XMI writer)", file=sys.stderr)
        return 2
    try:
        packages = [read_package(Path(folder)) for folder in args.packages]
        model, notes = packages_to_model(packages, cpp_identifier(args.name or target.stem))
    except ModelReadError as exc:
        print(exc.one_line(), file=sys.stderr)
        return 2
    for note in notes:
        print(f"earl-m2t: note: {note}", file=sys.stderr)
    content = to_sysml(model).encode("utf-8")
    too_large = size_problem(len(content))
    if too_large:  # what no command would read back
        print(f"earl-m2t: import fabric: {target}: the model would be {too_large}: nothing written",
              file=sys.stderr)
        return 2
    return write_model_file("import fabric", target, content, args.force, "import")

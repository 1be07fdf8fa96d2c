"""``earl-m2t profile --format papyrus|cameo|ea|ea-mdg -o DIR``: the EARL profile for a SysML tool.

Generates, from ``profiles/earl.sysml``, the profile file the tool imports and writes it
into DIR (through :mod:`earl_m2t.output`: atomically, unchanged files left alone). Prints
one line per file (``wrote DIR/x`` or ``unchanged DIR/x``); exit 0. A problem (DIR not
writable, the profile file broken) is one line on stderr, exit 2.
"""

from __future__ import annotations

import argparse
import sys

from earl_m2t.cli.profile_formats import profile_formats

_FORMAT_HELP = (
    "papyrus: EARL.profile.uml, an Eclipse UML2 profile, defined, for Papyrus; "
    "cameo: EARL.cameo.xmi, UML 2.5 XMI for Cameo Systems Modeler / MagicDraw; "
    "ea: EARL.ea.xmi, a UML profile in XMI for Enterprise Architect; "
    "ea-mdg: EARL.mdg.xml, an MDG Technology for Enterprise Architect"
)


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser(
        "profile",
        help="write the EARL profile for Papyrus, Cameo or Enterprise Architect",
        description="Write the EARL profile (from profiles/earl.sysml) as the profile file of a SysML tool.",
    )
    parser.add_argument("--format", required=True, choices=profile_formats(), help=_FORMAT_HELP)
    parser.add_argument("-o", "--output", required=True, metavar="DIR",
                        help="folder to write the profile into (created when missing)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from earl_m2t.output import OutputError, write_files
    from earl_m2t.profile_export.render import export_profile
    from earl_m2t.profile_export.spec import ProfileExportError
    from earl_m2t.profile_types import ProfileError

    try:
        files = export_profile(args.format)
        report = write_files(args.output, files)
    except (OutputError, ProfileError, ProfileExportError) as error:
        print(f"earl-m2t: profile: {error}", file=sys.stderr)
        return 2
    for line in report.lines():
        print(line)
    return 0

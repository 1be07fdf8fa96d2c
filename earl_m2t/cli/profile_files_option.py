"""The ``--profile FILE`` option of the commands that read models: Enterprise Architect profile
or MDG Technology files of profiles that specialise EARL (SPSysML's ``PhyAgent`` is an Agent)."""

from __future__ import annotations

import argparse


def add_profile_files_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--profile", action="append", default=[], metavar="FILE", dest="profiles",
        help="an Enterprise Architect profile (<UMLProfile>) or MDG Technology file whose stereotypes "
             "specialise EARL's (repeatable; such files beside the model, named *profile.xml, "
             "*.mdg.xml or *-mdg.xml, are read without it)",
    )

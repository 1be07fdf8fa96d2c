"""``python -m earl_m2t`` runs the command line."""

from earl_m2t.cli.app import entry

entry()

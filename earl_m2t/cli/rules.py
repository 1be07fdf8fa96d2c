"""``earl-m2t rules [CODE]``: list the rule catalogue, or explain one rule."""

from __future__ import annotations

import argparse
import sys


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("rules", help="list the rules, or explain one")
    parser.add_argument("code", nargs="?", metavar="CODE", help="a rule code (e.g. B005) or name")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    import json

    from earl_m2t.check.registry import catalogue, retired_codes

    rules = catalogue()
    if args.code:
        wanted = args.code.strip()
        info = rules.get(wanted.upper()) or next((r for r in rules.values() if r.name == wanted), None)
        if info is None:
            replacement = retired_codes().get(wanted.upper())
            hint = f"; it was retired in favour of {replacement}" if replacement else ""
            print(f"earl-m2t: no rule {wanted!r}{hint} (see earl-m2t rules)", file=sys.stderr)
            return 2
        selected = [info]
    else:
        selected = list(rules.values())
    if args.format == "json":
        rows = [
            {"code": r.code, "name": r.name, "severity": r.severity.value, "summary": r.summary,
             "source": r.source, "engine": r.engine, "doc": r.doc()}
            for r in selected
        ]
        sys.stdout.write(json.dumps(rows if not args.code else rows[0], indent=2, ensure_ascii=False) + "\n")
    elif args.code:
        sys.stdout.write(selected[0].doc())
    else:
        width = max(len(r.name) for r in selected)
        for r in selected:
            sys.stdout.write(f"{r.code}  {r.severity.value:<7}  {r.name:<{width}}  {r.summary}\n")
    return 0

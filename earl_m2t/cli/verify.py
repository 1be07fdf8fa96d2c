"""``earl-m2t verify MODEL``: system-level model checking with SPIN (docs/verify.md).

Exit codes: 0 every property holds, 1 a property fails (with a counterexample), 2 bad usage, an
unreadable model or SPIN missing, 3 not proven (a depth or time bound stopped the search).
"""

from __future__ import annotations

import argparse
import sys

from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.early_parse import parses_model_early
from earl_m2t.cli.profile_files_option import add_profile_files_option

EXIT_NOT_PROVEN = 3
# The keys of earl_m2t.verify.render.RENDERERS, named here so that the parser is built without
# importing the verifier (a test keeps the two equal).
OUTPUT_FORMATS = ("text", "json", "sarif", "github")


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser("verify", help="model-check the whole system with SPIN: reachability, deadlock, LTL")
    parser.add_argument("model", metavar="MODEL")
    parser.add_argument("--format", choices=OUTPUT_FORMATS, default="text")
    parser.add_argument("--depth", type=int, default=100_000, metavar="N",
                        help="the search depth bound (default 100000)")
    parser.add_argument("--timeout", type=float, default=120.0, metavar="S",
                        help="seconds for the whole run (default 120)")
    parser.add_argument("--ltl", action="append", default=[], metavar="FORMULA",
                        help="an LTL property over agent/subsystem@state and agent/subsystem.name/pp (a primitive "
                             "predicate's value in the subsystem's latest iteration), e.g. "
                             "'[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)'; with configurations "
                             "also config@NAME, switching and agent@active "
                             "('[] (config@useB -> !manipA/a@active)') "
                             "(repeatable; the model's own properties are checked too)")
    add_dialect_option(parser)
    add_profile_files_option(parser)
    parser.set_defaults(run=run)


@parses_model_early
def run(args: argparse.Namespace) -> int:
    from earl_m2t.api import load
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.model.directives import LtlProperty
    from earl_m2t.model.location import Location
    from earl_m2t.verify.ltl import LtlError, tokens
    from earl_m2t.verify.render import RENDERERS
    from earl_m2t.verify.run import VerifyOptions, verify_model
    from earl_m2t.verify.spin import SpinUnavailable

    if args.depth < 1 or args.timeout <= 0:
        print("earl-m2t: verify: --depth and --timeout must be positive", file=sys.stderr)
        return 2
    try:
        loaded = load(args.model, args.dialect, args.profiles)
    except ModelReadError as exc:
        print(exc.one_line(), file=sys.stderr)
        return 2
    model = loaded.model
    given = tuple(LtlProperty(f"ltl{i}", text, Location("--ltl", i + 1, 1)) for i, text in enumerate(args.ltl))
    written = tuple(LtlProperty(f"ltl{len(given) + i}", p.text, p.location, p.label)
                    for i, p in enumerate(loaded.properties))
    properties = written + given
    try:
        for prop in properties:
            tokens(prop, model)  # a syntax error or unknown state: one line before SPIN runs
        result = verify_model(model, VerifyOptions(args.depth, args.timeout, properties))
    except LtlError as exc:
        print(f"earl-m2t: verify: {exc}", file=sys.stderr)
        return 2
    except SpinUnavailable as exc:
        print(f"earl-m2t: verify: {exc}", file=sys.stderr)
        return 2
    sys.stdout.write(RENDERERS[args.format](str(args.model), result))
    if result.findings:
        return 1
    return EXIT_NOT_PROVEN if result.not_proven else 0

"""``earl-m2t verify MODEL``: system-level model checking with SPIN (docs/verify.md).

The model is checked first (with the configuration ``check`` uses): a model with error findings
is not translated unless ``--force`` (to see, say, the counterexample behind a rule's error);
they are printed and verify exits 2.

Exit codes: 0 every property holds, 1 a property fails (with a counterexample), 2 bad usage, an
unreadable model, a model with error findings or SPIN missing, 3 not proven (a depth or time
bound stopped the search).
"""

from __future__ import annotations

import argparse
import sys

from earl_m2t.cli.config_option import add_config_options
from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.cli.early_parse import parses_model_early
from earl_m2t.cli.profile_files_option import add_profile_files_option

EXIT_NOT_PROVEN = 3
# The keys of earl_m2t.verify.render.RENDERERS, named here so that the parser is built without
# importing the verifier (a test keeps the two equal).
OUTPUT_FORMATS = ("text", "json", "sarif", "github")
# The codes of earl_m2t.verify.run.CHECK_CODES, for the same reason (the same test).
CHECK_CODES = ("V001", "V002", "V003", "V004", "V005", "V006", "V007", "V008", "V009")


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
    parser.add_argument("--check", action="append", default=[], metavar="CODE", choices=CHECK_CODES,
                        help="decide only this check (V001-V009, repeatable; default every one), e.g. "
                             "'--check V006' for the switches' losses alone")
    add_dialect_option(parser)
    add_profile_files_option(parser)
    add_config_options(parser)
    parser.add_argument("--force", action="store_true", help="verify even when the model has error findings")
    parser.set_defaults(run=run)


@parses_model_early
def run(args: argparse.Namespace) -> int:
    from earl_m2t.cli.checked_model import read_and_check
    from earl_m2t.diagnostics import Severity
    from earl_m2t.model.directives import LtlProperty
    from earl_m2t.model.location import Location
    from earl_m2t.render.diagnostics import text_line
    from earl_m2t.verify.ltl import LtlError, tokens
    from earl_m2t.verify.render import RENDERERS
    from earl_m2t.verify.run import VerifyOptions, verify_model
    from earl_m2t.verify.spin import SpinUnavailable

    if args.depth < 1 or args.timeout <= 0:
        print("earl-m2t: verify: --depth and --timeout must be positive", file=sys.stderr)
        return 2
    checked = read_and_check(args, "verify")
    if isinstance(checked, int):
        return checked
    errors = [d for d in checked.findings if d.severity == Severity.ERROR]
    if errors and not args.force:
        for diagnostic in errors:
            print(text_line(diagnostic), file=sys.stderr)
        print(f"earl-m2t: verify: {len(errors)} error(s) in {args.model}; nothing verified (--force to verify "
              "anyway)", file=sys.stderr)
        return 2
    loaded = checked.loaded
    model = loaded.model
    if model.system is None:
        print(f"earl-m2t: verify: {args.model} holds no EARL system to verify", file=sys.stderr)
        return 2
    given = tuple(LtlProperty(f"ltl{i}", text, Location("--ltl", i + 1, 1)) for i, text in enumerate(args.ltl))
    written = tuple(LtlProperty(f"ltl{len(given) + i}", p.text, p.location, p.label)
                    for i, p in enumerate(loaded.properties))
    properties = written + given
    try:
        for prop in properties:
            tokens(prop, model)  # a syntax error or unknown state: one line before SPIN runs
        result = verify_model(model, VerifyOptions(args.depth, args.timeout, properties, frozenset(args.check)))
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

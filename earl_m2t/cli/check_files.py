"""``earl-m2t check`` at work: the model files checked one after the other, or by ``--jobs N``
worker processes (the output is the same), and the report in the chosen format."""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

from earl_m2t.api import check_loaded, load
from earl_m2t.check.engine import CheckOptions, load_rule_code
from earl_m2t.check.registry import catalogue
from earl_m2t.cli.check_settings import Settings, UsageError, settings
from earl_m2t.cli.discover import model_files
from earl_m2t.cli.progress import Progress
from earl_m2t.config import ConfigError
from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity, SourceTextError
from earl_m2t.read.bounded import ReadPolicy, reading_with
from earl_m2t.read.early import still_parsing
from earl_m2t.render.check_report import CheckReport
from earl_m2t.render.diagnostics import FORMATS


@dataclass(frozen=True)
class Outcome:
    """One file's result, as a worker process sends it back."""

    file: str
    diagnostics: list[Diagnostic]
    error: str = ""  # the one line of an unreadable file
    unreadable: dict[str, object] | None = None


def check_file(file: str, options: CheckOptions, dialect: str | None, policy: ReadPolicy,
               profiles: tuple[str, ...] = ()) -> Outcome:
    try:
        with reading_with(policy):
            return Outcome(file, check_loaded(load(file, dialect, profiles), options))
    except ModelReadError as exc:
        return Outcome(file, [], exc.one_line(), {"file": exc.file, "line": exc.line, "message": exc.message})


def _run_all(files: list[str], setup: Settings, dialect: str | None, jobs: int,
             profiles: tuple[str, ...] = ()) -> list[Outcome]:
    progress = Progress(len(files), sys.stderr)
    results: dict[str, Outcome] = {}
    try:
        if jobs <= 1 or len(files) <= 1:
            for index, file in enumerate(files, 1):
                progress.show(index, file)
                results[file] = check_file(file, setup.options_for(file), dialect, setup.read_policy(), profiles)
        else:
            from concurrent.futures import ProcessPoolExecutor, as_completed  # only for --jobs N

            with ProcessPoolExecutor(max_workers=min(jobs, len(files))) as pool:
                futures = {pool.submit(check_file, f, setup.options_for(f), dialect, setup.read_policy(),
                                       profiles): f for f in files}
                for done, future in enumerate(as_completed(futures), 1):
                    progress.show(done, futures[future])
                    results[futures[future]] = future.result()
    finally:
        progress.clear()
    return [results[file] for file in files]


def run_check(args: argparse.Namespace) -> int:
    if args.jobs < 1:
        print("earl-m2t: --jobs must be at least 1", file=sys.stderr)
        return 2
    try:
        setup = settings(args)
    except (ConfigError, UsageError, SourceTextError) as exc:
        print(str(exc).splitlines()[0], file=sys.stderr)
        return 2
    load_rule_code(worth_it=still_parsing)  # the rules' code loads while the model parses, not after
    files, empty = model_files(args.models)
    for folder in empty:
        print(f"{folder}: warning: no model files found", file=sys.stderr)
    outcomes = _run_all(files, setup, args.dialect, args.jobs, tuple(args.profiles))
    diagnostics = sorted((d for o in outcomes for d in o.diagnostics), key=Diagnostic.sort_key)
    for outcome in outcomes:
        if outcome.error:
            print(outcome.error, file=sys.stderr)
    checked = [o.file for o in outcomes if not o.error]
    unreadable = [o.unreadable for o in outcomes if o.unreadable is not None]
    options = setup.options
    ran = [c for c in catalogue() if options.enabled(c)] + [
        info.code for info, _ in options.extra_rules if options.enabled(info.code)]
    sys.stdout.write(FORMATS[args.format](CheckReport(diagnostics, checked, unreadable, rules=ran)))
    if unreadable:
        return 2
    return 1 if any(d.severity is Severity.ERROR for d in diagnostics) else 0

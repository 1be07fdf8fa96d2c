"""Read a model and check it with the repository's configuration, for the commands that
need the findings before they write anything (``gen``, ``report``)."""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

from earl_m2t.api import Loaded, check_loaded, load
from earl_m2t.cli.check_settings import UsageError, options_for_model
from earl_m2t.config import ConfigError
from earl_m2t.diagnostics import Diagnostic, ModelReadError, SourceTextError
from earl_m2t.read.bounded import reading_with


@dataclass(frozen=True)
class CheckedModel:
    loaded: Loaded
    findings: list[Diagnostic]


def read_and_check(args: argparse.Namespace, command: str) -> CheckedModel | int:
    """``args.model`` read and checked, or the exit code (2) after one line on stderr for an
    unusable configuration or an unreadable model."""
    try:
        options, policy = options_for_model(args, args.model)
    except (ConfigError, UsageError, SourceTextError) as error:
        print(str(error).splitlines()[0], file=sys.stderr)
        return 2
    try:
        with reading_with(policy):
            loaded = load(args.model, getattr(args, "dialect", None), getattr(args, "profiles", ()))
    except ModelReadError as error:
        print(f"earl-m2t: {command}: {error}", file=sys.stderr)
        return 2
    return CheckedModel(loaded, check_loaded(loaded, options))

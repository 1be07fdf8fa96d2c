"""Commands that read one model file parse it in the background while they import their
implementation (:mod:`earl_m2t.read.early`); this module stays light, so that building the
parser of the command line imports nothing of the readers."""

from __future__ import annotations

import argparse
import functools
from collections.abc import Callable

Run = Callable[[argparse.Namespace], int]


def parses_model_early(run: Run) -> Run:
    """``run`` with the file ``args.model`` parsed in the background from the start."""

    @functools.wraps(run)
    def run_with_early_parse(args: argparse.Namespace) -> int:
        from earl_m2t.read.early import parsing_early

        with parsing_early(getattr(args, "model", None)):
            return run(args)

    return run_with_early_parse

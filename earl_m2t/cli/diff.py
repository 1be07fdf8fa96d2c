"""``earl-m2t diff OLD NEW``: what changed between two models, in EARL terms.

Exit codes as ``diff``: 0 the same EARL model (nothing printed), 1 differences, 2 a model
that cannot be read (or cannot be generated, with ``--affected``). Either side may be a
file of any dialect, ``git:REV:PATH`` or ``/dev/null``.

``--git-external-diff`` makes it a git diff driver: git passes ``PATH OLD-FILE OLD-HEX
OLD-MODE NEW-FILE NEW-HEX NEW-MODE``; the EARL diff is printed under a header naming PATH
and the exit code is 0 (git stops at a driver that fails).
"""

from __future__ import annotations

import argparse
import sys
from contextlib import ExitStack
from pathlib import Path
from typing import TYPE_CHECKING

from earl_m2t.cli.dialect_option import add_dialect_option
from earl_m2t.gen_targets import gen_targets

if TYPE_CHECKING:
    from earl_m2t.diff import Change
    from earl_m2t.diff.sources import Side


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser(
        "diff", help="show what changed between two models, in EARL terms",
        description="Compare two models (any dialects, or git:REV:PATH) on the lifted EARL model. "
                    "Exit 0 when they are the same EARL model, 1 when they differ, 2 when one cannot be read.")
    parser.add_argument("models", nargs="+", metavar="MODEL",
                        help="OLD NEW: files, git:REV:PATH (a committed file) or /dev/null")
    parser.add_argument("--format", choices=("text", "markdown", "json"), default="text",
                        help="text (default), markdown (a pull-request comment) or json (docs/model-diff.md)")
    parser.add_argument("--affected", metavar="OUT_DIR", type=Path, default=None,
                        help="also list the files of OUT_DIR the change rewrites, orphans or adds (writes nothing)")
    parser.add_argument("--target", default=None, choices=[t.name for t in gen_targets()],
                        help="the gen target of OUT_DIR (with --affected)")
    parser.add_argument("--git-external-diff", action="store_true",
                        help="act as git's diff driver (diff.<driver>.command): take git's seven arguments")
    add_dialect_option(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.diff import sources

    if args.git_external_diff:
        if len(args.models) != 7:
            print("earl-m2t: diff --git-external-diff: expected git's seven arguments "
                  "(PATH OLD-FILE OLD-HEX OLD-MODE NEW-FILE NEW-HEX NEW-MODE)", file=sys.stderr)
            return 2
        return _git_driver(args)
    if len(args.models) != 2:
        print(f"earl-m2t: diff: expected OLD NEW, got {len(args.models)} model(s)", file=sys.stderr)
        return 2
    if (args.affected is None) != (args.target is None):
        print("earl-m2t: diff: --affected OUT_DIR and --target T go together", file=sys.stderr)
        return 2
    try:
        with ExitStack() as stack:
            old = stack.enter_context(sources.opened(args.models[0], args.dialect))
            new = stack.enter_context(sources.opened(args.models[1], args.dialect))
            return _report(old, new, args)
    except ModelReadError as error:
        print(f"earl-m2t: diff: {error.one_line()}", file=sys.stderr)
        return 2


def _report(old: Side, new: Side, args: argparse.Namespace) -> int:
    from earl_m2t.diff import formats

    changes = _changes(old, new)
    if not changes:
        return 0
    affected = None
    if args.affected is not None:
        from earl_m2t.diff.affected import affected_files
        from earl_m2t.gen import GenError

        try:
            files = affected_files(old.model, new.model, args.affected, args.target)
        except GenError as error:
            print(f"earl-m2t: diff: --affected: {error}", file=sys.stderr)
            return 2
        affected = formats.Affected(args.affected.as_posix(), args.target, files)
    sys.stdout.write(formats.render(changes, old.label, new.label, args.format, affected))
    return 1


def _changes(old: Side, new: Side) -> list[Change]:
    from dataclasses import replace

    from earl_m2t.diff import compare
    from earl_m2t.diff.tree import diff_tree
    from earl_m2t.element_tree.nodes import Node
    from earl_m2t.model.location import Location

    empty = Node("EarlModel", "model", "", "", "", Location(""), (), ())

    def tree(side: Side) -> Node:
        return diff_tree(side.model) if side.model is not None else empty

    changes = compare(tree(old), tree(new))
    if old.model is None or new.model is None:  # a whole model added or removed: its name is no change
        changes = [c for c in changes if c.kind != "model"]
    for side in (old, new):
        if side.read_from:
            changes = [replace(c, where=side.shown_as + c.where.removeprefix(side.read_from))
                       if c.where.startswith(side.read_from) else c for c in changes]
    return changes


def _git_driver(args: argparse.Namespace) -> int:
    from earl_m2t.diagnostics import ModelReadError
    from earl_m2t.diff import formats, sources

    path, old_file, _old_hex, _old_mode, new_file, _new_hex, _new_mode = args.models
    try:
        with ExitStack() as stack:
            old = stack.enter_context(sources.opened(old_file, args.dialect))
            new = stack.enter_context(sources.opened(new_file, args.dialect))
            changes = _changes(old, new)
    except ModelReadError as error:
        sys.stdout.write(f"earl-m2t diff {path}\n{error.one_line()}\n")
        return 0
    if changes:
        text = formats.render(changes, f"a/{path}", f"b/{path}", args.format)
        sys.stdout.write(f"earl-m2t diff a/{path} b/{path}\n" + text if args.format == "text" else text)
    return 0

"""``earl-m2t trace FILE:LINE …``: the model element a generated line comes from; ``earl-m2t
trace -`` copies compiler output from stdin to stdout and adds, under each diagnostic in a
generated file, a note at the model element (``MODEL:LINE: note: …``, which editors follow).

The source map is the ``.earl-trace.json`` that ``gen`` writes in the output folder; it is
looked for in the folders above each file. Exit codes: 0 every line traced (always for
``-``), 1 a line of a file no source map names, 2 bad arguments or an unreadable source map.
"""

from __future__ import annotations

import argparse
import re
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from earl_m2t.trace.lookup import SourceMaps

_FILE_LINE = re.compile(r"^(?P<file>.+):(?P<line>\d+)$")


def add_parser(commands: argparse._SubParsersAction) -> None:
    parser = commands.add_parser(
        "trace", help="show the model element a generated line comes from",
        description="Map generated lines back to model elements with the source map (.earl-trace.json) of their "
                    "output folder. '-' reads compiler output from stdin and adds a note at the model element "
                    "under each diagnostic in a generated file.")
    parser.add_argument("locations", nargs="+", metavar="FILE:LINE", help="a generated file and line, or - for stdin")
    parser.add_argument("--format", choices=("text", "json"), default="text")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from earl_m2t.trace.lookup import SourceMaps, TraceError

    maps = SourceMaps()
    try:
        if args.locations == ["-"]:
            return _filter_compiler_output(maps)
        return _trace_locations(maps, args.locations, args.format)
    except TraceError as error:
        print(f"earl-m2t: trace: {error}", file=sys.stderr)
        return 2


def _trace_locations(maps: SourceMaps, locations: list[str], fmt: str) -> int:
    import json

    parsed = []
    for location in locations:
        match = _FILE_LINE.match(location)
        if match is None:
            print(f"earl-m2t: trace: {location}: expected FILE:LINE (or - for compiler output on stdin)",
                  file=sys.stderr)
            return 2
        parsed.append((location, match.group("file"), int(match.group("line"))))
    code = 0
    results = []
    for location, file, line in parsed:
        origin = maps.origin(file, line)
        if origin is None:
            print(f"earl-m2t: trace: {file}: no source map (.earl-trace.json) in the folders above names it",
                  file=sys.stderr)
            code = 1
            continue
        if fmt == "json":
            results.append({"generated": location, "element": origin.element or None, "kind": origin.kind or None,
                            "xmi_id": origin.xmi_id or None, "file": origin.model_file or None,
                            "line": origin.model_line or None, "user_file": origin.user_file})
        elif origin.element:
            print(f"{origin.where}: {origin.describe()} <- {location}")
        else:
            print(f"{location}: {origin.describe()}")
    if fmt == "json":
        sys.stdout.write(json.dumps(results, indent=2, ensure_ascii=False) + "\n")
    return code


def _filter_compiler_output(maps: SourceMaps) -> int:
    from earl_m2t.trace.lookup import COMPILER_LINE

    for raw in sys.stdin:
        sys.stdout.write(raw)
        match = COMPILER_LINE.match(raw)
        if match is None:
            continue
        origin = maps.origin(match.group("file"), int(match.group("line")))
        if origin is not None and origin.element:
            sys.stdout.write(f"{origin.where}: note: generated from {origin.describe()}\n")
        sys.stdout.flush()
    return 0

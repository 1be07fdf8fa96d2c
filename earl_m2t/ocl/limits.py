"""What the OCL parser refuses before parsing: a rule file is a repository's own text, but a
parser by descent must still end on any input in a one-line error, not a ``RecursionError``.

Refused (the parser reports it at the offending character) (strings and ``--`` comments are not counted):
parentheses nested more than ``MAX_NESTING`` deep, a run of more than ``MAX_NESTING`` prefix
operators (``not not … x``, ``- - x``), and more than ``MAX_OPERATORS`` operators in one
invariant. Deep ``if … endif`` or ``let … in`` chains, which no pre-scan counts as cheaply, are
caught where the parser runs out of depth (:func:`earl_m2t.ocl.parser.parse_invariants`).
"""

from __future__ import annotations

import re

from earl_m2t.model.limits import MAX_NESTING, MAX_OPERATORS

# strings and comments, each up to its end (an unclosed string up to the line's end)
_SKIPPED = re.compile(r"'(?:\\.|[^'\\\n])*'?|--[^\n]*")
_PARENTHESIS = re.compile(r"[()]")
_PREFIX_RUN = re.compile(rf"(?:(?<![\w])not(?![\w])\s*|-(?!>)\s*){{{MAX_NESTING + 1},}}")
_OPERATOR = re.compile(r"(?<![\w])(?:and|or|xor|implies|not)(?![\w])|<>|<=|>=|[=<>+*/]|-(?!>)")
_INVARIANT_START = re.compile(r"(?<![\w])context(?![\w])")


def oversized(text: str) -> tuple[int, str] | None:
    """Where ``text`` first nests or chains beyond the limits, and why; None when it does not."""
    code = _SKIPPED.sub(lambda skipped: " " * len(skipped.group(0)), text)
    depth = 0
    for parenthesis in _PARENTHESIS.finditer(code):
        if parenthesis.group(0) == "(":
            depth += 1
            if depth > MAX_NESTING:
                return parenthesis.start(), f"nested more than {MAX_NESTING} levels deep ('('): not read"
        else:
            depth = max(depth - 1, 0)
    run = _PREFIX_RUN.search(code)
    if run is not None:
        operator = run.group(0)[:3].strip()
        return run.start(), f"more than {MAX_NESTING} prefix operators in a row ('{operator}'): not read"
    starts = [found.start() for found in _INVARIANT_START.finditer(code)]
    for begin, end in zip([0, *starts], [*starts, len(code)]):
        operators = _OPERATOR.findall(code, begin, end)
        if len(operators) > MAX_OPERATORS:
            return begin, f"an invariant of more than {MAX_OPERATORS} operators: not read"
    return None


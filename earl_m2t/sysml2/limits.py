"""What the SysML v2 reader refuses before parsing: control characters, nesting beyond
``MAX_NESTING``, a run of more than ``MAX_NESTING`` prefix operators (``not not … x``: each
one a level of the parser's recursion, as a bracket is) and an expression of more than
``MAX_OPERATORS`` operators (each costs the parser a descent through every precedence level).

Both are reported as ``file:line:col: error: ...`` at the offending character. Control
characters (C0 other than tab, line feed and carriage return; DEL; C1; U+FFFE, U+FFFF) cannot be
written into names, strings or XMI, and are invisible in review; nesting (``{``, ``(``, ``[``,
counted over the whole text) deeper than ``MAX_NESTING`` levels is refused rather
than parsed, so that every input ends in a model or a one-line error. One linear pass each.
"""

from __future__ import annotations

import re

from earl_m2t.model.limits import MAX_NESTING, MAX_OPERATORS

# The parser (textX on Arpeggio, a PEG parser in pure Python) reads some 70 KB of SysML v2 text
# a second; a larger text is refused before it is parsed, so that every command on a model ends
# within seconds (the samples are under 30 KB). docs/untrusted-models.md lists it.
MAX_TEXT_BYTES = 1 << 20


def size_problem(size: int) -> str:
    """Why SysML v2 text of ``size`` bytes (UTF-8) is not read, or "" when it is not too large."""
    if size <= MAX_TEXT_BYTES:
        return ""
    return f"SysML v2 text of {size:,} bytes, more than the {MAX_TEXT_BYTES:,} (1 MiB) the reader parses"

_CONTROL = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\ufffe\uffff]")
# what the nesting count skips: strings, quoted names, comments (each up to its end, or the file's)
_SKIPPED = re.compile(r"""'(?:[^'\\]|\\.)*'?|"(?:[^"\\]|\\.)*"?|/\*.*?(?:\*/|\Z)|//[^\n]*""", re.DOTALL)
_OPEN = "{(["
_BRACKET = re.compile(r"[{}()\[\]]")
_ESCAPE = re.compile(r"\\(.)", re.DOTALL)
_CONTROL_ESCAPES = "bf"
# prefix operators one after the other: ``not``, ``-``, ``+``, ``~``
_PREFIX_RUN = re.compile(rf"(?:(?<![\w'])not(?![\w'])\s*|[-+~]\s*){{{MAX_NESTING + 1},}}")
# an expression never holds ';', '{' or '}': the operators between two of them belong to one at most
_OPERATOR = re.compile(r"(?<![\w'])(?:or|and|xor|implies|not)(?![\w'])|[|&=<>!+\-*/%^~]+|[{};]")


class Refused(Exception):
    def __init__(self, offset: int, message: str) -> None:
        self.offset = offset
        self.message = message
        super().__init__(message)


def refuse_unreadable(text: str) -> None:
    """Raise :class:`Refused` (with the offset) for a control character or nesting beyond ``MAX_NESTING``."""
    control = _CONTROL.search(text)
    if control is not None:
        code = ord(control.group(0))
        raise Refused(control.start(), f"control character U+{code:04X} is not allowed in SysML v2 text")
    index = 0
    length = len(text)
    while index < length:  # strings and quoted names: no escape that makes a control character
        char = text[index]
        if char in "'\"/":
            skipped = _SKIPPED.match(text, index)
            if skipped is not None and skipped.end() > index:
                if char != "/":
                    _refuse_control_escape(skipped.group(0), index)
                index = skipped.end()
                continue
        index += 1
    # Nesting is counted over the whole text, strings and comments included: where a string or
    # comment ends is the parser's to decide (an unclosed quote), and real models never come near.
    depth = 0
    for bracket in _BRACKET.finditer(text):
        if bracket.group(0) in _OPEN:
            depth += 1
            if depth > MAX_NESTING:
                raise Refused(bracket.start(), f"nested more than {MAX_NESTING} levels deep "
                                               f"('{bracket.group(0)}'): not read")
        else:
            depth = max(depth - 1, 0)
    blanked = _SKIPPED.sub(lambda skipped: " " * len(skipped.group(0)), text)
    run = _PREFIX_RUN.search(blanked)
    if run is not None:
        raise Refused(run.start(), f"more than {MAX_NESTING} prefix operators in a row ('{run.group(0)[:3].strip()}'): "
                                   "not read")
    _refuse_long_expression(blanked)


def _refuse_long_expression(code: str) -> None:
    """More than ``MAX_OPERATORS`` operators between two of ';', '{', '}' (strings and comments blanked)."""
    count = 0
    start = 0
    for found in _OPERATOR.finditer(code):
        if found.group(0) in "{};":
            count = 0
            continue
        if count == 0:
            start = found.start()
        count += 1
        if count > MAX_OPERATORS:
            raise Refused(start, f"an expression of more than {MAX_OPERATORS} operators: not read")


def _refuse_control_escape(quoted: str, offset: int) -> None:
    """``\\b`` and ``\\f`` in a string or quoted name would give a control character."""
    for escape in _ESCAPE.finditer(quoted):
        if escape.group(1) in _CONTROL_ESCAPES:
            raise Refused(offset + escape.start(), f"escape '{escape.group(0)}' gives a control character, "
                          "which is not allowed in SysML v2 names and strings")


def line_and_column(text: str, offset: int) -> tuple[int, int]:
    """1-based line and column of a character offset."""
    return text.count("\n", 0, offset) + 1, offset - (text.rfind("\n", 0, offset) + 1) + 1

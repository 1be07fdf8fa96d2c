"""A model repository's own rules: invariants of the rule language with a severity and a message.

    -- severity: warning
    -- message: agent {path} has more than 8 virtual effectors
    context Agent inv team.max-effectors: self.ve->size() <= 8

The ``-- key: value`` comments right above an invariant (keys ``severity`` and ``message``)
describe it; without them the severity is ``warning`` and the message names the context, the
element and the rule. The invariant's name is the findings' code. See docs/rule-language.md.
"""

from __future__ import annotations

import re
from functools import cache
from string import Formatter

from earl_m2t.check.registry import RuleInfo, catalogue
from earl_m2t.diagnostics import Severity, SourceTextError
from earl_m2t.ocl import Invariant

CONTEXTS = ("System", "Robot", "Agent", "Subsystem", "Buffer", "Memory", "State", "Link", "DataType")
_KEY = re.compile(r"\s*--\s*(severity|message)\s*:\s*(.*?)\s*$")
_PLAIN = re.compile(r"\s*--")

UserRule = tuple[RuleInfo, Invariant]


def _metadata(lines: list[str], line: int, file: str) -> tuple[dict[str, str], dict[str, int]]:
    """The ``-- key: value`` comments of the comment block right above 1-based ``line``."""
    values: dict[str, str] = {}
    where: dict[str, int] = {}
    index = line - 2
    while index >= 0 and _PLAIN.match(lines[index]):
        found = _KEY.match(lines[index])
        if found and found.group(1) not in values:
            if not found.group(2):
                raise SourceTextError(file, index + 1, 1, f"empty '{found.group(1)}'")
            values[found.group(1)] = found.group(2)
            where[found.group(1)] = index + 1
        index -= 1
    return values, where


@cache
def parse_user_rules(text: str, file: str) -> tuple[UserRule, ...]:
    """The rules of one file; raises :class:`SourceTextError` (``file:line:col: message``)."""
    from earl_m2t.ocl.parser import parse_invariants  # the grammar only for a repository with rule files

    lines = text.splitlines()
    builtin = catalogue()
    builtin_names = {info.name for info in builtin.values()}
    rules: list[UserRule] = []
    for invariant in parse_invariants(text, file):
        where = (file, invariant.line, invariant.column)
        if invariant.context not in CONTEXTS:
            raise SourceTextError(*where, f"unknown context '{invariant.context}' (known: {', '.join(CONTEXTS)})")
        if invariant.name.upper() in builtin or invariant.name in builtin_names:
            raise SourceTextError(*where, f"'{invariant.name}' is a built-in rule; give your rule another "
                                          f"name, such as team.{invariant.name}")
        values, lines_of = _metadata(lines, invariant.line, file)
        try:
            severity = Severity.parse(values.get("severity", "warning"))
        except ValueError:
            raise SourceTextError(file, lines_of["severity"], 1,
                                  f"severity must be error, warning or info, not '{values['severity']}'") from None
        field = "name" if invariant.context == "DataType" else "path"
        message = values.get("message") or f"{invariant.context.lower()} {{{field}}} breaks rule {invariant.name}"
        try:
            list(Formatter().parse(message))
        except ValueError as exc:
            raise SourceTextError(file, lines_of["message"], 1, f"message: {exc}") from None
        info = RuleInfo(code=invariant.name, name=invariant.name, severity=severity,
                        summary=f"{invariant.context}: {invariant.source}", source=file, engine="ocl",
                        message=message)
        rules.append((info, invariant))
    return tuple(rules)

"""The rule catalogue: one row per code, with its severity, summary and doc.

Rows come from ``metamodel/rules/catalogue.toml``; OCL rules are the invariants of
``metamodel/rules/invariants.ocl``; Python rules are implemented in :mod:`earl_m2t.check.rules`.
"""

from __future__ import annotations

import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cache

from earl_m2t.diagnostics import Severity
from earl_m2t.resources import metamodel_path


@dataclass(frozen=True, slots=True)
class RuleInfo:
    code: str
    name: str
    severity: Severity
    summary: str
    source: str
    engine: str  # "ocl" | "python" | "reader" | "spin" (found by `verify`)
    message: str  # message template of ocl rules

    @property
    def family(self) -> str:
        return self.code[0]

    @property
    def rationale(self) -> str:
        """The "Why it matters" paragraph of the rule's page."""
        doc = self.doc()
        _, found, rest = doc.partition("\n## Why it matters\n")
        return rest.split("\n## ", 1)[0].strip() if found else self.summary

    def doc(self) -> str:
        """The rule's page (what, why, bad and good example), or its summary when it has none."""
        path = metamodel_path("rules", "docs", f"{self.code}.md")
        if path.is_file():
            return path.read_text(encoding="utf-8")
        return f"# {self.code} {self.name} ({self.severity.value})\n\n{self.summary}\n"


@cache
def catalogue() -> dict[str, RuleInfo]:
    data = tomllib.loads(metamodel_path("rules", "catalogue.toml").read_text(encoding="utf-8"))
    rules = {}
    for code, row in data["rules"].items():
        rules[code] = RuleInfo(
            code=code,
            name=row["name"],
            severity=Severity.parse(row["severity"]),
            summary=row["summary"],
            source=row["source"],
            engine=row["engine"],
            message=row.get("message", ""),
        )
    return dict(sorted(rules.items(), key=lambda item: _code_order(item[0])))


@cache
def retired_codes() -> dict[str, str]:
    data = tomllib.loads(metamodel_path("rules", "catalogue.toml").read_text(encoding="utf-8"))
    return dict(data.get("retired", {}))


_FAMILY_ORDER = "SCBTDR"


def _code_order(code: str) -> tuple[int, str]:
    family = _FAMILY_ORDER.find(code[0])
    return (family if family >= 0 else len(_FAMILY_ORDER), code)


def select_codes(selectors: Iterable[str]) -> set[str]:
    """Expand ``--select`` / ``--ignore`` items: full codes, prefixes (``S``, ``B00``) or rule names."""
    known = catalogue()
    chosen: set[str] = set()
    for selector in selectors:
        item = selector.strip()
        if not item:
            continue
        matches = {code for code, info in known.items() if code.startswith(item.upper()) or info.name == item}
        if not matches:
            raise KeyError(item)
        chosen |= matches
    return chosen

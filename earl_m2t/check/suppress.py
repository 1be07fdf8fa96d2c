"""Suppressions written in the model (:class:`~earl_m2t.model.directives.Suppression`, a comment
``earl-m2t: ignore[C008] reason`` on an element) applied to the findings.

A suppression silences its rules for findings on the elements it annotates: findings whose
location has that element's xmi:id, or whose element path is the path of a lifted element read
from it. A suppression that silences nothing is R005; one without a reason is R006 (it still
silences).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import fields, is_dataclass

from earl_m2t.check.engine import CheckOptions
from earl_m2t.check.registry import catalogue
from earl_m2t.diagnostics import Diagnostic
from earl_m2t.model.conditions import Condition
from earl_m2t.model.directives import Suppression
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location
from earl_m2t.model.scope import Scope


def _objects(value: object, seen: set[int]) -> Iterator[object]:
    """Every lifted element reachable from ``value`` (dataclasses, tuples, mappings)."""
    if id(value) in seen or isinstance(value, (str, int, float, bool)) or value is None:
        return
    seen.add(id(value))
    if is_dataclass(value) and not isinstance(value, type):
        yield value
        if isinstance(value, (Condition, Scope)):  # what the lift made of a text: no element in it
            return
        for f in fields(value):
            yield from _objects(getattr(value, f.name), seen)
    elif isinstance(value, Mapping):
        for item in value.values():
            yield from _objects(item, seen)
    elif isinstance(value, (tuple, list, frozenset, set)):
        for item in value:
            yield from _objects(item, seen)


def element_paths(model: EarlModel, ids: set[str]) -> dict[str, set[str]]:
    """The paths of the lifted elements read from the elements with these xmi:ids."""
    paths: dict[str, set[str]] = {}
    for obj in _objects(model, set()):
        location = getattr(obj, "location", None)
        path = getattr(obj, "path", "")
        if isinstance(location, Location) and location.xmi_id in ids and path:
            paths.setdefault(location.xmi_id, set()).add(path)
    return paths


def _resolve(written: str, user_codes: set[str]) -> str:
    """The code a suppression names: a code, a built-in rule's name or a repository rule's name; "" if none."""
    rules = catalogue()
    if written.upper() in rules:
        return written.upper()
    by_name = {info.name: code for code, info in rules.items()}
    if written in by_name:
        return by_name[written]
    return written if written in user_codes else ""


def apply_suppressions(diagnostics: Iterable[Diagnostic], model: EarlModel, options: CheckOptions) -> list[Diagnostic]:
    """The findings none of the model's suppressions silences, plus R005 / R006 findings about
    the suppressions."""
    suppressions = model.suppressions
    kept = list(diagnostics)
    if not suppressions:
        return kept
    user_codes = {info.code for info, _ in options.extra_rules}
    paths = element_paths(model, {s.target for s in suppressions})
    used: set[tuple[int, str]] = set()
    silenced: set[int] = set()
    for index, suppression in enumerate(suppressions):
        codes = {_resolve(c, user_codes) for c in suppression.codes} - {""}
        where = paths.get(suppression.target, set())
        for position, diag in enumerate(kept):
            if diag.code in codes and ((suppression.target and diag.location.xmi_id == suppression.target)
                                       or diag.element in where):
                silenced.add(position)
                used.add((index, diag.code))
    result = [d for position, d in enumerate(kept) if position not in silenced]
    return result + list(_reports(suppressions, used, paths, options, user_codes))


def _reports(suppressions: tuple[Suppression, ...], used: set[tuple[int, str]], paths: dict[str, set[str]],
             options: CheckOptions, user_codes: set[str]) -> Iterator[Diagnostic]:
    rules = catalogue()
    for index, s in enumerate(suppressions):
        element = min(paths.get(s.target, set()), default="") or s.target_name
        if options.enabled("R006") and not s.reason:
            yield Diagnostic("R006", options.severity(rules["R006"]),
                             f"the suppression ignore[{', '.join(s.codes)}] on {s.target_name} gives no reason; "
                             "write why after the codes", s.location, element)
        if not options.enabled("R005"):
            continue
        if not s.codes:
            yield Diagnostic("R005", options.severity(rules["R005"]),
                             f"the suppression ignore[] on {s.target_name} names no rule", s.location, element)
        for written in s.codes:
            code = _resolve(written, user_codes)
            if not code:
                message = f"the suppression on {s.target_name} names '{written}', which is no rule"
            elif (index, code) in used or not options.enabled(code):
                continue
            else:
                message = f"the suppression of {code} on {s.target_name} is unused: no {code} finding there"
            yield Diagnostic("R005", options.severity(rules["R005"]), message, s.location, element)

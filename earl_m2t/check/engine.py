"""Stage 3: run the selected rules over a lifted model and return sorted diagnostics."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from functools import cache, partial
from pathlib import Path

from earl_m2t.cache import cached
from earl_m2t.check.per_configuration import PER_CONFIGURATION, per_configuration
from earl_m2t.check.registry import RuleInfo, catalogue
from earl_m2t.check.rule import Finding, RuleFunction
from earl_m2t.check.tables import LinkTable, using_permitted_links
from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location
from earl_m2t.model.variability import is_variable
from earl_m2t.ocl import Invariant, OclEvaluationError
from earl_m2t.ocl import check as ocl_check
from earl_m2t.resources import metamodel_path


@dataclass(frozen=True)
class CheckOptions:
    select: frozenset[str] | None = None  # None: every rule
    ignore: frozenset[str] = frozenset()
    severities: tuple[tuple[str, Severity], ...] = ()  # per-rule severity overrides
    permitted_links: LinkTable | None = None  # C002's table; None: metamodel/tables/permitted-links.toml
    extra_rules: tuple[tuple[RuleInfo, Invariant], ...] = ()  # a model repository's own invariants

    def enabled(self, code: str) -> bool:
        return (self.select is None or code in self.select) and code not in self.ignore

    def severity(self, info: RuleInfo) -> Severity:
        return dict(self.severities).get(info.code, info.severity)


@cache
def builtin_invariants() -> tuple[Invariant, ...]:
    path = metamodel_path("rules", "invariants.ocl")
    return cached("invariants", path, lambda: _parse_invariants(path))


def _parse_invariants(path: Path) -> tuple[Invariant, ...]:
    from earl_m2t.ocl.parser import parse_invariants  # the grammar only on a cache miss

    return tuple(parse_invariants(path.read_text(encoding="utf-8"), str(path)))


def load_rule_code(worth_it: Callable[[], bool]) -> None:
    """Import the rule implementations and the SAT solver now, not on first use, one after the
    other while ``worth_it()`` holds: ``check`` does so while the model parses in the background
    (:mod:`earl_m2t.read.early`), where the imports cost no wall time.

    networkx stays imported on first use, after the model is built: imported before, it raised
    the peak memory of checking the 10 MB bench model by about 10 MB (8 %), as the memory that
    reading and lifting free is then not reused for it."""
    for load in (_python_rules, _load_solver):
        if not worth_it():
            return
        load()


def _python_rules() -> dict[str, RuleFunction]:
    from earl_m2t.check.rules import python_rules  # the rule modules on first use (see load_rule_code)

    return python_rules()


def _load_solver() -> None:
    import pysat.solvers  # noqa: F401


def context_objects(model: EarlModel, context: str) -> Iterator[object]:
    """The objects an OCL ``context`` type ranges over; replicated subsystems count once."""
    if context == "System":
        yield from model.systems
    elif context == "Robot":
        yield from model.robots
    elif context == "Agent":
        yield from model.agents
    elif context == "Subsystem":
        yield from model.definitions()
    elif context == "Buffer":
        for sub in model.definitions():
            yield from sub.buffers
    elif context == "Memory":
        for sub in model.definitions():
            yield from sub.memory
    elif context == "State":
        for sub in model.definitions():
            if sub.fsm is not None:
                yield from sub.fsm.states
    elif context == "Link":
        yield from model.links
    elif context == "DataType":
        yield from model.datatypes.values()
    else:
        raise KeyError(context)


class _Fields(dict):
    """Message formatting: ``{path}``, ``{name}`` … from the element's attributes."""

    def __init__(self, element: object) -> None:
        super().__init__()
        self.element = element

    def __missing__(self, key: str) -> str:
        return str(getattr(self.element, key, "?"))


def run_invariant(info: RuleInfo, invariant: Invariant, model: EarlModel) -> Iterator[Finding]:
    for obj in context_objects(model, invariant.context):
        try:
            holds = ocl_check(invariant, obj)
        except OclEvaluationError as exc:
            holds = False
            message = f"{info.message.format_map(_Fields(obj))} (rule could not be evaluated: {exc})"
        else:
            message = info.message.format_map(_Fields(obj))
        if not holds:
            yield Finding(message, obj.location, getattr(obj, "path", getattr(obj, "name", "")))  # type: ignore[attr-defined]


def check_model(model: EarlModel, options: CheckOptions | None = None) -> list[Diagnostic]:
    """Every finding of the enabled rules, deduplicated and sorted by location."""
    options = options or CheckOptions()
    rules = catalogue()
    implementations = _python_rules()
    found: list[Diagnostic] = []
    if not model.systems:
        if options.enabled("R003"):
            info = rules["R003"]
            if model.has_earl_content:
                message = (f"{model.file} has EARL elements but no System: a block stereotyped «System», or a "
                           "top-level block whose parts are robots or agents, is needed")
            else:
                message = f"{model.file} holds no EARL model (no System, Robot or Agent recognised)"
            found.append(Diagnostic("R003", options.severity(info), message, Location(model.file, 1)))
        return found
    invariants: dict[str, list[Invariant]] = {}
    for invariant in builtin_invariants():
        invariants.setdefault(invariant.name, []).append(invariant)
    with using_permitted_links(options.permitted_links):
        for code, info in rules.items():
            if not options.enabled(code):
                continue
            if info.engine != "ocl" and code not in implementations:
                continue
            findings = _rule_findings(info, model, invariants, implementations)
            if code in PER_CONFIGURATION and is_variable(model):
                general = list(findings)
                run = partial(_rule_findings, info, invariants=invariants, implementations=implementations)
                findings = general + per_configuration(model, general, run)
            severity = options.severity(info)
            found.extend(Diagnostic(code, severity, f.message, f.location, f.element) for f in findings)
    for info, invariant in options.extra_rules:
        if options.enabled(info.code):
            severity = options.severity(info)
            found.extend(Diagnostic(info.code, severity, f.message, f.location, f.element)
                         for f in run_invariant(info, invariant, model))
    return deduplicate(found)


def _rule_findings(info: RuleInfo, model: EarlModel, invariants: dict[str, list[Invariant]],
                   implementations: dict[str, RuleFunction]) -> Iterable[Finding]:
    if info.engine == "ocl":
        return (f for inv in invariants.get(info.code, []) for f in run_invariant(info, inv, model))
    return implementations[info.code](model)


def deduplicate(diagnostics: Iterable[Diagnostic]) -> list[Diagnostic]:
    """One finding per rule and source position: replicated instances share their definition."""
    seen: set[tuple[str, str, int, int, str, str]] = set()
    unique = []
    for diag in diagnostics:
        loc = diag.location
        key = (diag.code, loc.file, loc.line, loc.column, loc.xmi_id, _template(diag.message))
        if key not in seen:
            seen.add(key)
            unique.append(diag)
    return sorted(unique, key=Diagnostic.sort_key)


def _template(message: str) -> str:
    """Messages of replicated instances differ only in the instance index."""
    return "".join("#" if ch.isdigit() else ch for ch in message)

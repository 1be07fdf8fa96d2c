"""T rules: transition functions, their stages and partial transition functions (eqs. 7-8, Figs. 6, 15)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from earl_m2t.analysis.switching import silent_outputs
from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import BasicBehaviour, EarlModel, Subsystem


@dataclass(frozen=True, slots=True)
class _Pf:
    """A pf with what it reads and writes worked out once (each is asked for in every stage)."""

    name: str
    reads: tuple[str, ...]  # paths, in model order, without repeats
    writes: tuple[str, ...]


def _functions(sub: Subsystem) -> dict[str, _Pf]:
    """The pfs of a subsystem by name; the first of a name, as ``Subsystem.function`` finds it."""
    table: dict[str, _Pf] = {}
    for pf in sub.functions:
        if pf.name not in table:
            table[pf.name] = _Pf(pf.name, tuple(dict.fromkeys(pf.reads)), tuple(dict.fromkeys(pf.writes)))
    return table


def _stage_conflicts(sub: Subsystem, functions: dict[str, _Pf], targets: set[str],
                     bb: BasicBehaviour) -> Iterator[tuple[int, str, list[str]]]:
    """(stage number, written element, writers) where two pf of one stage write the same element of ``targets``."""
    for number, stage in enumerate(bb.stages, start=1):
        writers: dict[str, list[str]] = {}
        for pf_name in stage:
            pf = functions.get(pf_name)
            if pf is None:
                continue
            for written in pf.writes:
                if written in targets:
                    writers.setdefault(written, []).append(pf_name)
        for written, names in writers.items():
            if len(names) > 1:
                yield number, written, names


def _stage_rule(model: EarlModel, want_memory: bool) -> Iterator[Finding]:
    kind = "memory" if want_memory else "output buffer"
    for sub in model.definitions():
        # replicated instances are reported by the name the model gives them (windingCurrentK/m)
        template = {b.path: b.template for b in sub.outputs} | {m.path: m.template for m in sub.memory}
        targets = {m.path for m in sub.memory} if want_memory else {b.path for b in sub.outputs}
        functions = _functions(sub)
        for bb in sub.behaviours:
            grouped: dict[tuple[int, tuple[str, ...]], list[str]] = {}
            for number, written, names in _stage_conflicts(sub, functions, targets, bb):
                shown = grouped.setdefault((number, tuple(names)), [])
                if template[written] not in shown:
                    shown.append(template[written])
            for (number, writers), elements in grouped.items():
                yield Finding(f"{bb.path}: stage {number} runs {' and '.join(writers)} in parallel and both write "
                              f"{kind} {', '.join(elements)}", bb.location, bb.path)


@rule("T001")
def stage_memory_write_conflict(model: EarlModel) -> Iterator[Finding]:
    return _stage_rule(model, want_memory=True)


@rule("T002")
def stage_output_write_conflict(model: EarlModel) -> Iterator[Finding]:
    return _stage_rule(model, want_memory=False)


@rule("T003")
def pf_foreign_access(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        for pf in sub.functions:
            for access in pf.accesses:
                if access.foreign:
                    yield Finding(f"{pf.path} {access.mode}s '{access.name}', which belongs to {access.foreign}, "
                                  f"not to {sub.path}", access.location, pf.path)
                elif not access.targets:
                    yield Finding(f"{pf.path} {access.mode}s '{access.name}', which is no buffer or memory of "
                                  f"{sub.path}", access.location, pf.path)


@rule("T005")
def tf_activity_malformed(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        known = {pf.name for pf in sub.functions}
        for bb in sub.behaviours:
            for problem in bb.activity_problems:
                yield Finding(f"{bb.path}: {problem.message}", problem.location, bb.path)
            for pf_name in bb.functions:
                if pf_name not in known:
                    yield Finding(f"{bb.path} calls '{pf_name}', which is no partial transition function of "
                                  f"{sub.path}", bb.location, bb.path)


@rule("T004")
def stage_read_write_race(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        template = {m.path: m.template for m in sub.memory}
        table = _functions(sub)
        for bb in sub.behaviours:
            for number, stage in enumerate(bb.stages, start=1):
                functions = [pf for pf in (table.get(name) for name in stage) if pf is not None]
                races: dict[tuple[str, str], list[str]] = {}
                for reader in functions:
                    own = set(reader.writes)  # a pf that also writes the memory is T001's concern
                    for read in reader.reads:
                        if read not in template or read in own:
                            continue
                        for writer in functions:
                            if writer is not reader and read in writer.writes:
                                shown = races.setdefault((writer.name, reader.name), [])
                                if template[read] not in shown:
                                    shown.append(template[read])
                for (writer_name, reader_name), memories in races.items():
                    yield Finding(f"{bb.path}: stage {number} runs {writer_name} and {reader_name} in parallel; "
                                  f"{reader_name} reads memory {', '.join(memories)} that {writer_name} writes "
                                  "(race: the value read depends on timing)", bb.location, bb.path)


@rule("T006")
def output_buffer_not_written(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        table = _functions(sub)
        for bb in sub.behaviours:
            functions = [table.get(name) for name in bb.functions]
            if bb.activity_problems or any(pf is None for pf in functions):
                continue  # a malformed tf is T005's; its writes are not known
            written = {path for pf in functions if pf is not None for path in pf.writes}
            silent = silent_outputs(model, sub, bb.name)  # its links closed wherever bb runs: nothing is sent
            stale = list(dict.fromkeys(b.template for b in sub.outputs if b.path not in written
                                       and b.template not in silent))
            if stale:
                plural = "s" if len(stale) > 1 else ""
                yield Finding(f"{bb.path}: no partial transition function of its tf writes output buffer{plural} "
                              f"{', '.join(stale)}, so send() repeats stale data", bb.location, bb.path)

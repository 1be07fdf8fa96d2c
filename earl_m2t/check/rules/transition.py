"""T rules: transition functions, their stages and partial transition functions (eqs. 7-8, Figs. 6, 15)."""

from __future__ import annotations

from typing import Iterator

from earl_m2t.check.registry import Finding, rule
from earl_m2t.model.elements import BasicBehaviour, EarlModel, Subsystem


def _stage_conflicts(sub: Subsystem, bb: BasicBehaviour, want_memory: bool) -> Iterator[tuple[int, str, list[str]]]:
    """(stage number, written element, writers) where two pf of one stage write the same element."""
    outputs = {b.path for b in sub.outputs}
    memory = {m.path for m in sub.memory}
    targets = memory if want_memory else outputs
    for number, stage in enumerate(bb.stages, start=1):
        writers: dict[str, list[str]] = {}
        for pf_name in stage:
            pf = sub.function(pf_name)
            if pf is None:
                continue
            for written in dict.fromkeys(pf.writes):
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
        for bb in sub.behaviours:
            grouped: dict[tuple[int, tuple[str, ...]], list[str]] = {}
            for number, written, names in _stage_conflicts(sub, bb, want_memory):
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
        for bb in sub.behaviours:
            for number, stage in enumerate(bb.stages, start=1):
                functions = [pf for pf in (sub.function(name) for name in stage) if pf is not None]
                races: dict[tuple[str, str], list[str]] = {}
                for reader in functions:
                    own = set(reader.writes)  # a pf that also writes the memory is T001's concern
                    for read in dict.fromkeys(reader.reads):
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
        for bb in sub.behaviours:
            functions = [sub.function(name) for name in bb.functions]
            if bb.activity_problems or any(pf is None for pf in functions):
                continue  # a malformed tf is T005's; its writes are not known
            written = {path for pf in functions if pf is not None for path in pf.writes}
            stale = list(dict.fromkeys(b.template for b in sub.outputs if b.path not in written))
            if stale:
                plural = "s" if len(stale) > 1 else ""
                yield Finding(f"{bb.path}: no partial transition function of its tf writes output buffer{plural} "
                              f"{', '.join(stale)}, so send() repeats stale data", bb.location, bb.path)

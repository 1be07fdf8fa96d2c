"""Generate a target's files for a model and write them (generation gap included).

Generated files are rewritten whenever their content changes; user files (one per pf and
per primitive predicate written in user code) are created once and never touched again.
What an earlier run wrote and the model no longer produces (a user file; a ROS message or a
diagram of a renamed element) is reported as orphaned and kept.

Every target is declared in ``transforms/targets.toml`` (:mod:`earl_m2t.gen.declared`): the
renderer that makes its files and the orphans it looks for. Each run builds the views its
renderer reads once (:class:`earl_m2t.gen.target.Views`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from earl_m2t.gen.declared import GenTarget, declared_target
from earl_m2t.gen.engine import load_target
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.orphans import orphans_of
from earl_m2t.gen.rendered import Rendered
from earl_m2t.gen.target import TargetRun, Views
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.variability import is_variable
from earl_m2t.output import WriteReport, write_files
from earl_m2t.trace.sourcemap import with_source_map

__all__ = ["GenReport", "generate", "render"]


@dataclass(frozen=True)
class GenReport:
    write: WriteReport
    orphans: tuple[str, ...]  # user files, messages, diagrams (relative paths) the model no longer produces
    notes: tuple[str, ...] = ()  # what the target could not express (Rendered.notes)

    def lines(self) -> list[str]:
        return self.write.lines() + [f"orphaned {self.write.out_dir / path} (kept; nothing in the model "
                                     "generates it any more)" for path in self.orphans] + [
            f"note: {note}" for note in self.notes]


def render(model: EarlModel, target: str = "cpp", templates: Path | None = None,
           strict: bool = True) -> Rendered:
    """Every file of ``target`` for ``model``, in memory. Raises GenError.

    ``strict`` (the default; ``--force`` turns it off) makes the msg target refuse model
    names that cannot become ROS names or that collide; the cpp target leaves names to the
    check (rules D003, D004) and always mangles."""
    return _render(declared_target(target), model, templates, strict)


def _render(target: GenTarget, model: EarlModel, templates: Path | None, strict: bool) -> Rendered:
    if not target.variable_structure and is_variable(model):
        names = ", ".join(c.name for system in model.systems for c in system.configurations)
        raise GenError(f"--target {target.name} does not switch configurations yet (the model has {names}); "
                       f"--target cpp runs a variable structure")
    views = Views(model, strict, target.renderer.views)
    return target.renderer.render(TargetRun(target.name, load_target(target.name), templates, views))


def generate(model: EarlModel, out_dir: Path | str, target: str = "cpp",
             templates: Path | None = None, strict: bool = True) -> GenReport:
    """Render and write; user files are created only when missing. Raises GenError, OutputError."""
    declared = declared_target(target)
    rendered = _render(declared, model, templates, strict)
    generated = with_source_map(rendered.generated, rendered.user, model, target, out_dir)
    report = write_files(out_dir, generated, create_only=rendered.user)
    return GenReport(report, orphans_of(declared.orphans, Path(out_dir), rendered), rendered.notes)

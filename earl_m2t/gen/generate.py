"""Generate a target's files for a model and write them (generation gap included).

Generated files are rewritten whenever their content changes; user files (one per pf and
per primitive predicate written in user code) are created once and never touched again.
A user file that the model no longer produces is reported as orphaned and kept.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

from earl_m2t.gen.engine import environment, load_target, render as render_template, target_dir
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.views.cpp import CppTarget, build_view
from earl_m2t.model.elements import EarlModel
from earl_m2t.output import WriteReport, write_files

__all__ = ["GenError", "GenReport", "Rendered", "USER_FILE_MARKER", "generate", "render"]

#: First line of every user file the generator creates; how orphans are recognised.
USER_FILE_MARKER = b"// earl-m2t user file:"
TARGETS = ("cpp",)


@dataclass(frozen=True)
class Rendered:
    generated: dict[str, bytes]  # relative path -> bytes, always (re)written
    user: dict[str, bytes]  # relative path -> bytes, created once


@dataclass(frozen=True)
class GenReport:
    write: WriteReport
    orphans: tuple[str, ...]  # user files (relative paths) the model no longer produces

    def lines(self) -> list[str]:
        return self.write.lines() + [f"orphaned {self.write.out_dir / path} (kept; nothing in the model "
                                     "generates it any more)" for path in self.orphans]


def render(model: EarlModel, target: str = "cpp", templates: Path | None = None) -> Rendered:
    """Every file of ``target`` for ``model``, in memory. Raises GenError."""
    if target not in TARGETS:
        raise GenError(f"unknown target {target!r} (one of {', '.join(TARGETS)})")
    spec = load_target(target)
    capacities, executor = spec.get("capacities", {}), spec.get("executor", {})
    cpp = CppTarget(types=dict(spec["types"]), string_capacity=int(capacities.get("string", 64)),
                    unbounded_capacity=int(capacities.get("unbounded_array", 16)),
                    cycles=int(executor.get("cycles", 10)), period_ms=int(executor.get("period_ms", 1)))
    view = build_view(model, cpp)
    env = environment(target, templates)
    generated: dict[str, bytes] = {}
    user: dict[str, bytes] = {}
    ns = view.system["ns"]
    groups = spec["templates"]
    for template, pattern in sorted(groups["system"].items()):
        _put(generated, pattern.format(model=ns), render_template(env, template, system=view.system))
    for agent in view.agents:
        for template, pattern in sorted(groups["agent"].items()):
            _put(generated, pattern.format(model=ns, agent=agent["ns"]),
                 render_template(env, template, system=view.system, agent=agent))
    for sub in view.subsystems:
        for template, pattern in sorted(groups["subsystem"].items()):
            _put(generated, pattern.format(model=ns, agent=sub["agent"], sub=sub["sub"]),
                 render_template(env, template, system=view.system, sub=sub))
    for group, items in (("user_pf", view.user_pf), ("user_pp", view.user_pp)):
        for item in items:
            for template, pattern in sorted(groups[group].items()):
                _put(user, pattern.format(agent=item["agent"], sub=item["sub"], name=item["name"]),
                     render_template(env, template, item=item))
    runtime = target_dir(target) / spec.get("runtime", "runtime")
    for path in sorted(runtime.rglob("*")):
        if path.is_file():
            _put(generated, "runtime/" + path.relative_to(runtime).as_posix(), path.read_bytes())
    clash = sorted(set(generated) & set(user))
    if clash:
        raise GenError(f"a user file and a generated file share the path {clash[0]}")
    return Rendered(generated, user)


def _put(files: dict[str, bytes], path: str, content: bytes) -> None:
    key = path.lower()
    if any(existing.lower() == key for existing in files):
        raise GenError(f"two generated files map to the path {path}")
    files[path] = content


def generate(model: EarlModel, out_dir: Path | str, target: str = "cpp",
             templates: Path | None = None) -> GenReport:
    """Render and write; user files are created only when missing. Raises GenError, OutputError."""
    rendered = render(model, target, templates)
    report = write_files(out_dir, rendered.generated, create_only=rendered.user)
    return GenReport(report, find_orphans(Path(out_dir), set(rendered.user)))


def find_orphans(out_dir: Path, produced: set[str]) -> tuple[str, ...]:
    """User files under ``out_dir/user`` (marked as created by earl-m2t) not in ``produced``."""
    root = out_dir / "user"
    found: list[str] = []
    for folder, _dirs, names in os.walk(root, followlinks=False):
        for name in names:
            path = Path(folder) / name
            relative = PurePosixPath(path.relative_to(out_dir).as_posix())
            if str(relative) in produced or path.is_symlink():
                continue
            try:
                with path.open("rb") as stream:
                    head = stream.read(len(USER_FILE_MARKER))
            except OSError:
                continue
            if head == USER_FILE_MARKER:
                found.append(str(relative))
    return tuple(sorted(found))

"""The ``cpp`` target (``transforms/cpp/``): a CMake project with a class per subsystem, agent
and system over the header-only runtime, and a user file per pf and per primitive predicate
written in user code. The ``ros`` and ``orocos`` targets include its runtime, its generated
headers and its user files."""

from __future__ import annotations

from earl_m2t.gen.engine import load_target, target_dir
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.rendered import FileTable, Rendered, put_file
from earl_m2t.gen.target import Renderer, TargetRun, View, Views
from earl_m2t.gen.views.cpp import CppTarget, CppView, build_view


def _cpp_view(views: Views) -> CppView:
    spec = load_target("cpp")
    capacities, executor = spec.get("capacities", {}), spec.get("executor", {})
    settings = CppTarget(types=dict(spec["types"]), string_capacity=int(capacities.get("string", 64)),
                         unbounded_capacity=int(capacities.get("unbounded_array", 16)),
                         cycles=int(executor.get("cycles", 10)), period_ms=int(executor.get("period_ms", 1)),
                         switch_timeout=float(executor.get("switch_timeout_ms", 50)) / 1000)
    return build_view(views.model, settings)


VIEW = View("cpp", _cpp_view)


def _render(run: TargetRun) -> Rendered:
    view = run.views.get(VIEW)
    env = run.environment()
    generated = FileTable()
    user = FileTable()
    ns = view.system["ns"]
    groups = run.spec["templates"]
    for template, pattern in sorted(groups["system"].items()):
        put_file(generated, pattern.format(model=ns), render_template(env, template, system=view.system))
    for agent in view.agents:
        for template, pattern in sorted(groups["agent"].items()):
            put_file(generated, pattern.format(model=ns, agent=agent["ns"]),
                     render_template(env, template, system=view.system, agent=agent))
    for sub in view.subsystems:
        for template, pattern in sorted(groups["subsystem"].items()):
            put_file(generated, pattern.format(model=ns, agent=sub["agent"], sub=sub["sub"]),
                     render_template(env, template, system=view.system, sub=sub))
    for group, items in (("user_pf", view.user_pf), ("user_pp", view.user_pp)):
        for item in items:
            for template, pattern in sorted(groups[group].items()):
                put_file(user, pattern.format(agent=item["agent"], sub=item["sub"], name=item["name"]),
                         render_template(env, template, item=item))
    runtime = target_dir(run.name) / run.spec.get("runtime", "runtime")
    skipped = set() if view.system.get("switching") else set(run.spec.get("switch_runtime", ()))
    for path in sorted(runtime.rglob("*")):
        relative = path.relative_to(runtime).as_posix()
        if path.is_file() and relative not in skipped:
            put_file(generated, "runtime/" + relative, path.read_bytes())
    return beside_user_files(generated, user)


RENDERER = Renderer(views=(VIEW,), render=_render)


def runtime_and_headers(cpp: Rendered, prefix: str) -> FileTable:
    """The C++ target's runtime and generated headers, which the ROS and Orocos code includes."""
    generated = FileTable()
    for path, content in sorted(cpp.generated.items()):
        if path.startswith(("runtime/", "generated/include/")):
            put_file(generated, prefix + path, content)
    return generated


def beside_user_files(generated: dict[str, bytes], user: dict[str, bytes]) -> Rendered:
    """Generated files with user files, which they must not overwrite."""
    clash = sorted(set(generated) & set(user))
    if clash:
        raise GenError(f"a user file and a generated file share the path {clash[0]}")
    return Rendered(generated, user)

"""The ``orocos`` target (``transforms/orocos/``): Orocos RTT 2.x component libraries (a master
component per subsystem definition, a component per pf), deployer scripts and the FABRIC
subsystem models and run-time configurations, next to the ``cpp`` target's runtime, headers
and user files."""

from __future__ import annotations

from earl_m2t.gen.engine import load_target, target_dir
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.rendered import Rendered, put_file
from earl_m2t.gen.target import Renderer, TargetRun, View, Views
from earl_m2t.gen.targets import cpp, msg
from earl_m2t.gen.views.orocos import FABRIC_FOLDER, OrocosTarget, OrocosView, build_view


def _orocos_view(views: Views) -> OrocosView:
    settings = OrocosTarget.from_spec(load_target("orocos"), dict(load_target("ros")["std_msgs"]))
    return build_view(views.model, views.get(cpp.VIEW), views.get(msg.VIEW), msg.msg_settings(), settings)


VIEW = View("orocos", _orocos_view)


def _render(run: TargetRun) -> Rendered:
    cpp_files = cpp.RENDERER.render(run.for_target("cpp"))
    view = run.views.get(VIEW)
    env = run.environment()
    generated = cpp.runtime_and_headers(cpp_files, "")
    runtime = target_dir(run.name) / "runtime"  # the RTT side of the runtime, beside the C++ target's
    for path in sorted(runtime.rglob("*")):
        if path.is_file():
            put_file(generated, "runtime/" + path.relative_to(runtime).as_posix(), path.read_bytes())
    groups, system = run.spec["templates"], view.system
    for template, pattern in sorted(groups["system"].items()):
        put_file(generated, pattern, render_template(env, template, system=system))
    fabric = f"{FABRIC_FOLDER}/"
    for definition in view.definitions:
        for template, pattern in sorted(groups["definition"].items()):
            if definition["fabric"] is None and pattern.startswith(fabric):
                continue
            put_file(generated, pattern.format(agent=definition["agent"], sub=definition["sub"]),
                     render_template(env, template, system=system, d=definition, f=definition["fabric"]))
    for instance in view.instances:
        for template, pattern in sorted(groups["instance"].items()):
            if instance["fabric"] is None and pattern.startswith(fabric):
                continue
            put_file(generated, pattern.format(instance=instance["name"], package=instance["package"]),
                     render_template(env, template, system=system, i=instance))
    rendered = cpp.beside_user_files(generated, cpp_files.user)
    return Rendered(rendered.generated, rendered.user, tuple(view.notes))


RENDERER = Renderer(views=cpp.RENDERER.views + (msg.VIEW, VIEW), render=_render)

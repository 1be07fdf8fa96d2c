"""The ``ros`` target (``transforms/ros/``): catkin packages, namely the messages (the ``msg``
target), one package per agent (a node per subsystem definition, a launch file) and
``<model>_bringup`` (the system's launch file), next to the ``cpp`` target's runtime and
headers under ``earl/`` and its user files."""

from __future__ import annotations

from earl_m2t.gen.engine import load_target
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.rendered import Rendered, put_file
from earl_m2t.gen.target import Renderer, TargetRun, View, Views
from earl_m2t.gen.targets import cpp, msg
from earl_m2t.gen.views.ros import RosTarget, RosView, build_view


def _ros_view(views: Views) -> RosView:
    return build_view(views.model, views.get(cpp.VIEW), views.get(msg.VIEW), msg.msg_settings(),
                      RosTarget.from_spec(load_target("ros")), views.strict)


VIEW = View("ros", _ros_view)


def _render(run: TargetRun) -> Rendered:
    cpp_files = cpp.RENDERER.render(run.for_target("cpp"))
    msg_files = msg.RENDERER.render(run.for_target("msg"))
    view = run.views.get(VIEW)
    env = run.environment()
    generated = cpp.runtime_and_headers(cpp_files, "earl/")
    for path, content in sorted(msg_files.generated.items()):
        put_file(generated, path, content)
    system, groups = view.system, run.spec["templates"]
    names = {"msgs": system["msgs"], "bringup": system["bringup"], "model": view.convert["ns"].removesuffix("_ros")}
    for template, pattern in sorted(groups["msgs"].items()):
        put_file(generated, pattern.format(**names), render_template(env, template, system=system))
    if system["switch"]:
        for template, pattern in sorted(groups["switch_msgs"].items()):
            put_file(generated, pattern.format(**names), render_template(env, template, system=system))
    for template, pattern in sorted(groups["system"].items()):
        put_file(generated, pattern.format(**names),
                 render_template(env, template, system=system, convert=view.convert))
    for package in view.packages:
        for template, pattern in sorted(groups["agent"].items()):
            put_file(generated, pattern.format(package=package["name"], **names),
                     render_template(env, template, system=system, package=package))
    for node in view.nodes:
        for template, pattern in sorted(groups["node"].items()):
            put_file(generated, pattern.format(package=node["package"], node=node["exe"].removesuffix("_node"),
                                               **names),
                     render_template(env, template, system=system, node=node))
    return cpp.beside_user_files(generated, cpp_files.user)


RENDERER = Renderer(views=cpp.RENDERER.views + msg.RENDERER.views + (VIEW,), render=_render)

"""The ``ros2`` target (``transforms/ros2/``): ament_cmake packages for ROS 2 Jazzy, namely the
messages (the ``msg`` target's messages in ROS 2 syntax, through ``rosidl_generate_interfaces``), one package per
agent (an rclcpp component per subsystem definition) and ``<model>_bringup`` (the system's
launch file, composed or as separate processes, and one per host when the model allocates
agents to hosts), next to the ``cpp`` target's runtime and
headers under ``earl/`` and its user files. Its view starts from the ``ros`` target's."""

from __future__ import annotations

import json
import math
import unicodedata

from earl_m2t.gen.engine import load_target
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.rendered import MSG_FILE_MARKER, Rendered, put_file
from earl_m2t.gen.target import Renderer, TargetRun, View, Views
from earl_m2t.gen.targets import cpp, msg, ros
from earl_m2t.gen.views.ros2 import Ros2Target, Ros2View, build_view


def _ros2_view(views: Views) -> Ros2View:
    return build_view(views.model, views.get(ros.VIEW), views.get(msg.VIEW), Ros2Target.from_spec(load_target("ros2")))


VIEW = View("ros2", _ros2_view)


def _yaml_char(char: str) -> str:
    """A character of a double-quoted YAML scalar: itself when YAML may print it, else escaped."""
    code = ord(char)
    printable = 0x20 <= code <= 0x7E or (code >= 0xA0 and char not in "\u2028\u2029\ufeff"
                                          and unicodedata.category(char) not in ("Cs", "Co", "Cn"))
    if printable:
        return char
    return f"\\u{code:04x}" if code <= 0xFFFF else f"\\U{code:08x}"


def yaml_scalar(value: object) -> str:
    """A value as a YAML scalar of its own type, read alike by rcl's parameter parser and by
    PyYAML (launch_ros reads the file for composed nodes): a string double-quoted (so that
    ``true`` or ``1`` stays a string; JSON's escapes are YAML's), a float always with a point
    (PyYAML reads ``1e-06`` as a string)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float) and math.isfinite(value):
        mantissa, e, exponent = repr(value).partition("e")
        return (mantissa if "." in mantissa else mantissa + ".0") + e + exponent
    if isinstance(value, str):
        return "".join(map(_yaml_char, json.dumps(value, ensure_ascii=False)))
    raise GenError(f"no YAML scalar for the parameter value {value!r}")


def _render(run: TargetRun) -> Rendered:
    cpp_files = cpp.RENDERER.render(run.for_target("cpp"))
    view = run.views.get(VIEW)
    env = run.environment()
    env.filters["yaml"] = yaml_scalar
    generated = cpp.runtime_and_headers(cpp_files, "earl/")
    system, groups = view.system, run.spec["templates"]
    for message in view.messages:
        for template, pattern in sorted(groups["message"].items()):
            content = render_template(env, template, model=system["model"], package=system["msgs"], message=message)
            if not content.startswith(MSG_FILE_MARKER):
                raise GenError(f"template {template} must start with {MSG_FILE_MARKER.decode()!r}")
            put_file(generated, pattern.format(package=system["msgs"], message=message["name"]), content)
    names = {"msgs": system["msgs"], "bringup": system["bringup"], "manager": system["manager"],
             "model": view.convert["ns"].removesuffix("_ros2")}
    for template, pattern in sorted(groups["msgs"].items()):
        put_file(generated, pattern.format(**names), render_template(env, template, system=system))
    if system["switch"]:  # a model with configurations: the switch's messages
        for template, pattern in sorted(groups["switch_msgs"].items()):
            put_file(generated, pattern.format(**names), render_template(env, template, system=system))
    for template, pattern in sorted(groups["system"].items()):
        put_file(generated, pattern.format(**names),
                 render_template(env, template, system=system, convert=view.convert, launch=view.launch))
    for launch in view.hosts:
        for template, pattern in sorted(groups.get("host", {}).items()):
            put_file(generated, pattern.format(host=launch["host"], **names),
                     render_template(env, template, system=system, convert=view.convert, launch=launch))
    for package in view.packages:
        for template, pattern in sorted(groups["agent"].items()):
            put_file(generated, pattern.format(package=package["name"], parameter_file=package["parameter_file"],
                                               **names),
                     render_template(env, template, system=system, package=package))
    for component in view.components:
        for template, pattern in sorted(groups["node"].items()):
            put_file(generated, pattern.format(package=component["package"], node=component["name"], **names),
                     render_template(env, template, system=system, node=component))
    return cpp.beside_user_files(generated, cpp_files.user)


RENDERER = Renderer(views=ros.RENDERER.views + (VIEW,), render=_render)

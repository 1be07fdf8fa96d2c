"""The ``msg`` target (``transforms/msg/``): a ROS message per dataType a buffer, a memory or a
link uses. The ``ros`` target includes its files; ``ros`` and ``orocos`` read its view."""

from __future__ import annotations

from earl_m2t.gen.engine import load_target
from earl_m2t.gen.engine import render as render_template
from earl_m2t.gen.errors import GenError
from earl_m2t.gen.rendered import MSG_FILE_MARKER, FileTable, Rendered, put_file
from earl_m2t.gen.target import Renderer, TargetRun, View, Views
from earl_m2t.gen.views.msg import MsgTarget, MsgView, build_view


def msg_settings() -> MsgTarget:
    """The settings of ``transforms/msg/target.toml`` the message view reads."""
    return MsgTarget.from_spec(load_target("msg"))


def _msg_view(views: Views) -> MsgView:
    return build_view(views.model, msg_settings(), views.strict)


VIEW = View("msg", _msg_view)


def _render(run: TargetRun) -> Rendered:
    view = run.views.get(VIEW)
    env = run.environment()
    generated = FileTable()
    for message in view.messages:
        for template, pattern in sorted(run.spec["templates"].items()):
            content = render_template(env, template, model=view.model, package=view.package, message=message)
            if not content.startswith(MSG_FILE_MARKER):
                raise GenError(f"template {template} must start with {MSG_FILE_MARKER.decode()!r}")
            put_file(generated, pattern.format(package=view.package, message=message["name"]), content)
    return Rendered(generated, {})


RENDERER = Renderer(views=(VIEW,), render=_render)

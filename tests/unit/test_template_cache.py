"""The compiled templates shared by every target environment (earl_m2t/gen/engine.py): a second
environment renders from the shared code, and a template whose text changed, or a user template
of the same name, is compiled anew rather than served stale."""

from __future__ import annotations

from pathlib import Path

from earl_m2t.gen.engine import environment, render


def rendered(env_templates: Path | None, name: str, **context: object) -> str:
    return bytes(render(environment("msg", env_templates), name, **context)).decode()


def test_a_changed_user_template_renders_its_new_text(tmp_path: Path) -> None:
    template = tmp_path / "probe.j2"
    template.write_text("first {{ value }}\n")
    assert rendered(tmp_path, "probe.j2", value=1) == "first 1\n"
    assert rendered(tmp_path, "probe.j2", value=2) == "first 2\n"  # served from the shared code
    template.write_text("second {{ value }}\n")
    assert rendered(tmp_path, "probe.j2", value=3) == "second 3\n"


def test_a_user_template_overrides_a_built_in_one_already_compiled(tmp_path: Path) -> None:
    built_in = next(p.name for p in sorted((Path(__file__).resolve().parents[2] / "transforms" / "msg"
                                             / "templates").glob("*.j2")))
    environment("msg").get_template(built_in)  # compiled and shared
    (tmp_path / built_in).write_text("mine\n")
    assert rendered(tmp_path, built_in) == "mine\n"

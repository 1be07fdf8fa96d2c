"""The `gen` targets listed in transforms/targets.toml, the renderers registered in the
generator, the target folders and the documentation pages are one and the same set."""

from __future__ import annotations

from pathlib import Path

from earl_m2t import resources
from earl_m2t.cli.app import build_parser
from earl_m2t.gen.generate import TARGETS
from earl_m2t.cli.gen_targets import gen_targets

ROOT = Path(__file__).resolve().parents[1]


def test_every_listed_target_has_a_renderer_and_nothing_else_does() -> None:
    assert [t.name for t in gen_targets()] == list(TARGETS)


def test_every_target_has_its_folder_and_its_documentation_page() -> None:
    for target in gen_targets():
        assert (resources.data_dir("transforms") / target.name / "target.toml").is_file(), target.name
        assert (ROOT / target.doc).is_file(), target.doc


def test_the_command_line_offers_exactly_the_listed_targets() -> None:
    parser = build_parser()
    args = parser.parse_args(["gen", "model.uml", "-o", "out"])
    assert args.target == gen_targets()[0].name
    for target in gen_targets():
        assert parser.parse_args(["gen", "m.uml", "--target", target.name, "-o", "out"]).target == target.name

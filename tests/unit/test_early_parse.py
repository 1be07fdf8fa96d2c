"""The background parse of ``check``'s model file (earl_m2t.read.early): the reader takes the
tree it made and indexes the same model, raises the same one-line error for a file it cannot
read, and reads the file itself when the parse does not apply."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from earl_m2t.api import check, load
from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.bounded import ReadPolicy, reading_with
from earl_m2t.read.early import parsing_early, still_parsing, take_parsed
from earl_m2t.read.xmi_index import read_raw_model

ROOT = Path(__file__).resolve().parents[2]

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
ARCHIVE = ROOT.parent / "shared" / "corpus" / "cameo" / "capella-bridge-statemodes-md19.mdzip"


def _read_error(path: Path) -> str:
    with pytest.raises(ModelReadError) as caught:
        read_raw_model(path)
    return caught.value.one_line()


def test_the_reader_takes_the_tree_parsed_in_the_background() -> None:
    with parsing_early(SAMPLE):
        raw = read_raw_model(SAMPLE)
        assert take_parsed(SAMPLE) is None  # taken once
    plain = read_raw_model(SAMPLE)
    assert raw.dialect == plain.dialect
    assert sorted(raw.by_id) == sorted(plain.by_id)
    assert raw.stereotypes.keys() == plain.stereotypes.keys()


def test_a_check_with_the_background_parse_finds_what_a_plain_check_finds(tmp_path: Path) -> None:
    broken = tmp_path / "broken.uml"
    broken.write_text(SAMPLE.read_text(encoding="utf-8").replace("operationalMove", "operational Move", 3),
                      encoding="utf-8")
    plain = check(broken)
    with parsing_early(broken):
        early = check(broken)
    assert plain and early == plain


@pytest.mark.parametrize("content", [
    "", "   ", "<xmi:XMI", "<a/><b/>",
    '<!DOCTYPE x [<!ENTITY e "e">]><x>&e;</x>',
])
def test_an_unreadable_file_gives_the_readers_own_error(tmp_path: Path, content: str) -> None:
    model = tmp_path / "model.uml"
    model.write_text(content, encoding="utf-8")
    expected = _read_error(model)
    with parsing_early(model):
        assert _read_error(model) == expected


def test_a_file_over_the_size_limit_is_refused_as_the_reader_refuses_it(tmp_path: Path) -> None:
    small = ReadPolicy(max_bytes=100)
    with reading_with(small):
        expected = _read_error(SAMPLE)
        with parsing_early(SAMPLE):
            assert _read_error(SAMPLE) == expected
    assert "more than the limit of 100 bytes" in expected


def test_a_policy_changed_before_the_tree_is_taken_makes_the_reader_read_again() -> None:
    with reading_with(ReadPolicy(max_bytes=100)):
        with parsing_early(SAMPLE):  # parsed under a limit that refuses the file ...
            with reading_with(ReadPolicy()):
                assert take_parsed(SAMPLE) is None  # ... so its error is not the reader's answer now
                assert read_raw_model(SAMPLE).by_id


def test_a_parse_nobody_takes_is_dropped_at_the_end_of_the_block() -> None:
    with parsing_early(SAMPLE):
        pass
    assert not still_parsing()
    assert take_parsed(SAMPLE) is None


def test_folders_fifos_and_sysml2_files_are_left_to_the_reader(tmp_path: Path) -> None:
    sysml = tmp_path / "model.sysml"
    sysml.write_text("package P;\n", encoding="utf-8")
    fifo = tmp_path / "model.uml"
    os.mkfifo(fifo)
    for path in (tmp_path, sysml, fifo):
        with parsing_early(path):
            assert take_parsed(path) is None


def test_a_project_archive_is_read_by_the_reader() -> None:
    with parsing_early(ARCHIVE):
        assert take_parsed(ARCHIVE) is None
    with parsing_early(ARCHIVE):
        early = load(ARCHIVE)
    assert early.model == load(ARCHIVE).model

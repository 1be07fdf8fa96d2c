"""The on-disk cache of derived data: reused while its inputs are unchanged, rebuilt when the
source file or a module of earl-m2t changes."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from earl_m2t import cache


@pytest.fixture
def cache_home(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.delenv("EARL_M2T_NO_CACHE", raising=False)
    return tmp_path


def test_an_entry_is_reused_until_its_source_changes(cache_home: Path) -> None:
    source = cache_home / "data.txt"
    source.write_text("one")
    builds: list[str] = []

    def build() -> str:
        builds.append(source.read_text())
        return source.read_text().upper()

    assert cache.cached("data", source, build) == "ONE"
    assert cache.cached("data", source, build) == "ONE"
    source.write_text("two")
    assert cache.cached("data", source, build) == "TWO"
    assert builds == ["one", "two"]


def test_a_changed_module_of_the_package_changes_the_key(tmp_path: Path) -> None:
    package = tmp_path / "package"
    (package / "sub").mkdir(parents=True)
    module = package / "sub" / "loader.py"
    module.write_text("x = 1\n")
    (package / "notes.txt").write_text("not code")
    before = cache._code_stamp(package)
    os.utime(module, ns=(0, 0))
    assert cache._code_stamp(package) != before
    (package / "notes.txt").write_text("still not code, and not part of the stamp")
    assert cache._code_stamp(package) == cache._code_stamp(package)
    assert "notes.txt" not in cache._code_stamp(package)

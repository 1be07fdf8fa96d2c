"""The on-disk cache of derived data: reused while its inputs are unchanged, rebuilt when the
source file or a module of earl-m2t changes."""

from __future__ import annotations

import os
import time
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


def test_each_kind_keeps_its_most_recently_used_entries(cache_home: Path) -> None:
    """Entries of past sources are removed beyond KEPT_PER_KIND of a kind; one read again stays."""
    folder = cache_home / "cache" / "earl-m2t"
    sources = []
    past = time.time() - 10_000
    for number in range(cache.KEPT_PER_KIND + 5):
        source = cache_home / f"source{number}.txt"
        source.write_text(str(number))
        sources.append(source)
        cache.write_cached("kind", source, number)
        entry = folder / f"kind-{cache._key(source)}.pickle"
        os.utime(entry, (past + number, past + number))  # written one after the other, a second apart
        if number == cache.KEPT_PER_KIND - 4:
            assert cache.read_cached("kind", sources[0]) == 0  # used again: now the newest of all
    cache.write_cached("other", sources[0], "another kind")
    assert len(list(folder.glob("kind-*.pickle"))) == cache.KEPT_PER_KIND
    assert cache.read_cached("kind", sources[0]) == 0
    assert [cache.read_cached("kind", source) for source in sources[1:6]] == [None] * 5  # the oldest
    assert cache.read_cached("kind", sources[-1]) == len(sources) - 1
    assert cache.read_cached("other", sources[0]) == "another kind"

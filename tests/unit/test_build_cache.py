"""tests/support/build_cache.py: a build runs once per content, a changed input builds again, a
failed build leaves nothing that a later call would take for a build, and an entry a live test
process was handed is never pruned under it."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support import build_cache

ROOT = Path(__file__).resolve().parents[2]
HOLDER = """
import sys
from pathlib import Path
from tests.support import build_cache
folder = build_cache.built("cpp-x", Path(sys.argv[1]), lambda f: (f / "built").write_text("held"))
print(folder, flush=True)
sys.stdin.readline()
"""


@pytest.fixture(autouse=True)
def cache_home(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.delenv("EARL_BUILD_CACHE", raising=False)
    monkeypatch.setattr(build_cache, "_IN_USE", {})
    yield tmp_path / "cache"
    for folder in list(build_cache._IN_USE):
        build_cache.release(folder)


def source_tree(folder: Path, content: str = "int main() { return 0; }\n") -> Path:
    (folder / "generated").mkdir(parents=True)
    (folder / "generated" / "main.cpp").write_text(content)
    (folder / "CMakeLists.txt").write_text("project(x)\n")
    return folder


class CountingBuild:
    def __init__(self) -> None:
        self.folders: list[Path] = []

    def __call__(self, folder: Path) -> None:
        self.folders.append(folder)
        (folder / "built").write_text((folder / build_cache.SOURCE / "generated" / "main.cpp").read_text())


def test_the_same_content_is_built_once_and_a_second_tree_of_it_gets_that_build(tmp_path: Path) -> None:
    build = CountingBuild()
    first = build_cache.built("cpp-x", source_tree(tmp_path / "a"), build, ["-O2"])
    second = build_cache.built("cpp-x", source_tree(tmp_path / "b"), build, ["-O2"])
    assert first == second and len(build.folders) == 1
    assert (first / "built").read_text() == "int main() { return 0; }\n"
    assert (first / build_cache.SOURCE / "CMakeLists.txt").is_file()


@pytest.mark.parametrize("change", ["content", "recipe", "kind", "executable", "new file"])
def test_any_change_of_what_the_build_reads_is_a_new_build(tmp_path: Path, change: str) -> None:
    build = CountingBuild()
    first = build_cache.built("cpp-x", source_tree(tmp_path / "a"), build, ["-O2"])
    other = source_tree(tmp_path / "b", "int main() { return 1; }\n" if change == "content" else
                        "int main() { return 0; }\n")
    if change == "executable":
        os.chmod(other / "CMakeLists.txt", 0o755)
    if change == "new file":
        (other / "generated" / "extra.hpp").write_text("")
    second = build_cache.built("cpp-y" if change == "kind" else "cpp-x", other, build,
                               ["-O0"] if change == "recipe" else ["-O2"])
    assert first != second and len(build.folders) == 2


def test_the_source_map_with_the_models_path_is_no_part_of_the_key(tmp_path: Path) -> None:
    first, second = source_tree(tmp_path / "a"), source_tree(tmp_path / "b")
    (first / ".earl-trace.json").write_text('{"model": "/one/place.uml"}')
    (second / ".earl-trace.json").write_text('{"model": "/another/place.uml"}')
    build = CountingBuild()
    assert build_cache.built("cpp-x", first, build) == build_cache.built("cpp-x", second, build)


def test_a_failed_build_leaves_no_entry_and_the_next_call_builds_again(tmp_path: Path) -> None:
    def failing(folder: Path) -> None:
        (folder / "half").write_text("")
        raise AssertionError("cmake failed")

    source = source_tree(tmp_path / "a")
    with pytest.raises(AssertionError, match="cmake failed"):
        build_cache.built("cpp-x", source, failing)
    build = CountingBuild()
    folder = build_cache.built("cpp-x", source, build)
    assert len(build.folders) == 1 and not (folder / "half").exists()


def test_only_the_most_recently_used_entries_are_kept(tmp_path: Path) -> None:
    build = CountingBuild()
    folders = [build_cache.built("cpp-x", source_tree(tmp_path / str(n), f"// {n}\n"), build) for n in range(4)]
    for age, folder in enumerate(reversed(folders)):  # the first built is the least recently used
        os.utime(folder / build_cache.COMPLETE, (1_000_000 - age, 1_000_000 - age))
        build_cache.release(folder)
    build_cache.prune(keep=2)
    assert [folder.is_dir() for folder in folders] == [False, False, True, True]


def test_turned_off_it_builds_in_a_fresh_folder_every_time(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("EARL_BUILD_CACHE", "0")
    build = CountingBuild()
    source = source_tree(tmp_path / "a")
    assert build_cache.built("cpp-x", source, build) != build_cache.built("cpp-x", source, build)
    assert len(build.folders) == 2


def test_an_entry_a_running_process_holds_survives_every_prune_until_it_exits(tmp_path: Path) -> None:
    """A module fixture keeps a built folder for all its tests while the other worker writes
    new entries; the prune those trigger must not remove it."""
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, str(source_tree(tmp_path / "held"))],
                              cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}, text=True,
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    try:
        assert holder.stdout is not None and holder.stdin is not None
        held = Path(holder.stdout.readline().strip())
        assert (held / "built").read_text() == "held"
        mine = build_cache.built("cpp-x", source_tree(tmp_path / "mine", "// mine\n"), CountingBuild())
        build_cache.prune(keep=0)
        assert (held / "built").is_file(), "pruned while the process it was handed to still runs"
        assert (mine / "built").is_file(), "pruned while this process holds it"
        holder.stdin.write("\n")
        holder.stdin.flush()
        assert holder.wait(timeout=30) == 0
    finally:
        holder.kill()
    build_cache.release(mine)
    build_cache.prune(keep=0)
    assert not held.exists() and not mine.exists(), "an entry no process holds, beyond KEEP, stays"

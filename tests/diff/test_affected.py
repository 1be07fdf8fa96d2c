"""``earl-m2t diff --affected OUT_DIR --target T``: the files a change touches, without writing;
checked against what ``gen`` then really does in the folder."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from earl_m2t.trace import TRACE_FILE
from tests.diff import variants
from tests.diff.variants import ROOT, SAMPLE


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)


def snapshot(folder: Path) -> dict[str, tuple[bytes, int]]:
    return {p.relative_to(folder).as_posix(): (p.read_bytes(), p.stat().st_mtime_ns)
            for p in folder.rglob("*") if p.is_file()}


def affected(out: Path, new: Path, target: str) -> dict[str, set[str]]:
    before = snapshot(out)
    result = earl("diff", str(SAMPLE), str(new), "--affected", str(out), "--target", target)
    assert result.returncode == 1, result.stderr
    assert snapshot(out) == before  # nothing written
    text = result.stdout.split("\n\n", 1)[1]
    found: dict[str, set[str]] = {}
    for line in text.splitlines():
        action, path = line.split()
        found.setdefault(action, set()).add(Path(path).relative_to(out).as_posix())
    return found


def gen_report(out: Path, model: Path, target: str) -> dict[str, set[str]]:
    result = earl("gen", str(model), "--target", target, "-o", str(out), "--force")
    assert result.returncode == 0, result.stderr
    found: dict[str, set[str]] = {}
    for line in result.stdout.splitlines():
        action, path = line.split()[:2]
        found.setdefault(action, set()).add(Path(path).relative_to(out).as_posix())
    return found


@pytest.mark.parametrize("edit,target", [("removed_subsystem", "cpp"), ("renamed_pf", "cpp"),
                                         ("changed_guard", "orocos"), ("added_link", "ros")])
def test_affected_files_are_what_gen_then_does(tmp_path: Path, edit: str, target: str) -> None:
    out = tmp_path / "out"
    gen_report(out, SAMPLE, target)
    new = variants.write(tmp_path, f"{edit}.uml", getattr(variants, edit)(variants.sample_text()))
    listed = affected(out, new, target)
    done = gen_report(out, new, target)
    assert listed.get("rewrites", set()) | listed.get("generates", set()) == done.get("wrote", set()) - {TRACE_FILE}
    assert listed.get("adds", set()) == done.get("created", set())
    assert listed.get("orphans", set()) <= done.get("orphaned", set())
    assert listed.get("drops", set()) <= done.get("unchanged", set()) | set(snapshot(out))


def test_removed_subsystem_lists_dropped_files_and_the_orphaned_user_file(tmp_path: Path) -> None:
    out = tmp_path / "out"
    gen_report(out, SAMPLE, "cpp")
    new = variants.write(tmp_path, "removed.uml", variants.removed_subsystem(variants.sample_text()))
    assert affected(out, new, "cpp") == {
        "rewrites": {"generated/include/PickAndPlace/grip_a/agent.hpp", "generated/include/PickAndPlace/system.hpp"},
        "drops": {"generated/include/PickAndPlace/grip_a/fingerController_ve/data.hpp",
                  "generated/include/PickAndPlace/grip_a/fingerController_ve/subsystem.hpp"},
        "orphans": {"user/grip_a/fingerController_ve/regulateFinger_pf.hpp"},
    }


def test_renamed_pf_adds_a_user_file_and_orphans_the_old_one(tmp_path: Path) -> None:
    out = tmp_path / "out"
    gen_report(out, SAMPLE, "cpp")
    new = variants.write(tmp_path, "renamed.uml", variants.renamed_pf(variants.sample_text()))
    listed = affected(out, new, "cpp")
    assert listed["adds"] == {"user/grip_a/fingerController_ve/regulateFingers_pf.hpp"}
    assert listed["orphans"] == {"user/grip_a/fingerController_ve/regulateFinger_pf.hpp"}


def test_affected_needs_a_target_and_json_carries_it(tmp_path: Path) -> None:
    new = variants.write(tmp_path, "guard.uml", variants.changed_guard(variants.sample_text()))
    alone = earl("diff", str(SAMPLE), str(new), "--affected", str(tmp_path / "out"))
    assert alone.returncode == 2 and len(alone.stderr.splitlines()) == 1
    result = earl("diff", "--format", "json", str(SAMPLE), str(new), "--affected", "out", "--target", "cpp")
    assert result.returncode == 1
    document = json.loads(result.stdout)
    assert document["affected"] == {"out_dir": "out", "target": "cpp", "files": [
        {"action": "rewrites", "path": "generated/include/PickAndPlace/manip_a/cs/subsystem.hpp"}]}

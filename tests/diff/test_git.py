"""Models in git: ``git:REV:PATH`` sides, and ``git diff`` with the EARL diff driver of docs/ci.md."""

from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.diff import variants
from tests.diff.variants import SAMPLE, SAMPLES

pytestmark = pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")


def git(repo: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "GIT_AUTHOR_NAME": "t", "GIT_AUTHOR_EMAIL": "t@example.org", "GIT_COMMITTER_NAME": "t",
           "GIT_COMMITTER_EMAIL": "t@example.org", "GIT_CONFIG_NOSYSTEM": "1", "HOME": str(repo)}
    result = subprocess.run(["git", *args], cwd=repo, capture_output=True, text=True, env=env, timeout=120)
    assert result.returncode in (0, 1), result.stderr
    return result


def earl(repo: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=repo, capture_output=True, text=True,
                          timeout=120)


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    """A model repository: the sample committed in three dialects, the Papyrus one edited since."""
    folder = tmp_path / "models"
    folder.mkdir()
    git(folder, "init", "-q")
    (folder / "robot").mkdir()
    for name in ("pick_and_place.uml", "pick_and_place.ea.xml", "pick_and_place.sysml"):
        shutil.copy(SAMPLES / name, folder / "robot" / name)
    # the lines docs/ci.md gives, with this interpreter standing for the installed command
    (folder / ".gitattributes").write_text("*.uml diff=earl\n*.mdzip diff=earl\n*.sysml diff=earl\n"
                                           "robot/*.xml diff=earl\n", encoding="utf-8")
    command = f"{shlex.quote(sys.executable)} -m earl_m2t diff --git-external-diff"
    git(folder, "config", "diff.earl.command", command)
    git(folder, "add", ".")
    git(folder, "commit", "-qm", "the sample")
    model = folder / "robot" / "pick_and_place.uml"
    model.write_text(variants.changed_guard(model.read_text(encoding="utf-8")), encoding="utf-8")
    return folder


def test_git_revision_side_against_the_working_tree(repo: Path) -> None:
    result = earl(repo, "diff", "git:HEAD:robot/pick_and_place.uml", "robot/pick_and_place.uml")
    assert result.returncode == 1, result.stderr
    assert result.stdout == ("changed  transition manip/a.cs.fsm.idle,jointMove/t\n"
                             "           condition: newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun → newJointPos/pp.fun\n")
    same = earl(repo, "diff", "git:HEAD:robot/pick_and_place.uml", "git:HEAD:robot/pick_and_place.ea.xml")
    assert (same.returncode, same.stdout, same.stderr) == (0, "", "")


def test_git_side_locations_name_the_revision(repo: Path) -> None:
    result = earl(repo, "diff", "--format", "json", "robot/pick_and_place.uml", "git:HEAD:robot/pick_and_place.uml")
    text = SAMPLE.read_text(encoding="utf-8")
    line = text.count("\n", 0, text.index('name="idle,jointMove/t"')) + 1
    assert f'"where": "git:HEAD:robot/pick_and_place.uml:{line}"' in result.stdout


def test_unknown_revision_or_path_exits_2(repo: Path) -> None:
    for spec in ("git:nosuchrev:robot/pick_and_place.uml", "git:HEAD:robot/missing.uml", "git:HEAD"):
        result = earl(repo, "diff", spec, "robot/pick_and_place.uml")
        assert result.returncode == 2, spec
        assert len(result.stderr.splitlines()) == 1 and spec in result.stderr


def test_git_diff_with_the_driver_shows_the_earl_diff(repo: Path) -> None:
    result = git(repo, "diff")
    assert result.stdout == (
        "earl-m2t diff a/robot/pick_and_place.uml b/robot/pick_and_place.uml\n"
        "changed  transition manip/a.cs.fsm.idle,jointMove/t\n"
        "           condition: newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun → newJointPos/pp.fun\n")


def test_git_diff_of_a_re_export_and_of_a_new_model(repo: Path) -> None:
    """Replacing the EA export by a re-export with other ids is no EARL change; a new model
    file shows everything as added; git log -p needs --ext-diff."""
    git(repo, "commit", "-qam", "guard")
    ea = repo / "robot" / "pick_and_place.ea.xml"
    ea.write_text(variants.resaved(ea.read_text(encoding="latin-1")), encoding="latin-1")
    assert git(repo, "diff", "--stat").stdout.strip()  # the file did change
    assert git(repo, "diff").stdout == ""
    shutil.copy(SAMPLE, repo / "robot" / "copy.uml")
    git(repo, "add", "robot/copy.uml")
    added = git(repo, "diff", "--cached").stdout.splitlines()
    assert added[0] == "earl-m2t diff a/robot/copy.uml b/robot/copy.uml"
    assert added[1].startswith("added    system PickAndPlaceSystem (with 1 robot, 3 agents")
    log = git(repo, "log", "-p", "--ext-diff", "-1", "--format=%s").stdout.splitlines()
    assert log[:3] == ["guard", "", "earl-m2t diff a/robot/pick_and_place.uml b/robot/pick_and_place.uml"]

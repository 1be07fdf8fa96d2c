"""Hostile and broken models, as a linter of untrusted pull requests meets them (issue 15's
reproductions): every command ends in exit 0, 1 or 2 with a one-line error or a finding, never
an internal error, a hang or unbounded memory.

Each command runs as a user runs it, in its own process, under an address-space limit (an
unbounded read ends in MemoryError, an internal error) and a generous time bound that only
catches hangs.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
SAMPLE_SYSML = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"
MEMORY = 3 << 30  # bytes of address space a command may use
HANG = 300  # seconds: far beyond any of these commands, only a hang reaches it
# the href of one field's type in the sample (Vector3.x : Real)
REAL_HREF = 'href="pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#Real"'


def _limited() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))


def earl(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    result = subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                            timeout=HANG, preexec_fn=_limited)
    text = result.stdout + result.stderr
    assert "internal error" not in text and "Traceback" not in text, text[-2000:]
    assert result.returncode in (0, 1, 2), text[-2000:]
    return result


def _sample_with_href(folder: Path, href: str, name: str = "model.uml") -> Path:
    """The sample with the type of its first Real field pointing at ``href``."""
    text = SAMPLE.read_text(encoding="utf-8")
    assert REAL_HREF in text
    model = folder / name
    model.write_text(text.replace(REAL_HREF, f'href="{href}"', 1), encoding="utf-8")
    return model


def _r004(result: subprocess.CompletedProcess[str]) -> str:
    lines = [line for line in result.stdout.splitlines() if " R004 " in line]
    assert len(lines) == 1, result.stdout + result.stderr
    return lines[0]


# -- 1. unbounded reads through hrefs, and the model path itself ------------------------------------


def test_an_href_to_dev_zero_is_an_r004_finding_not_a_read(tmp_path: Path) -> None:
    model = _sample_with_href(tmp_path, "../../../../../../../../dev/zero#_0")
    result = earl("check", str(model))
    line = _r004(result)
    assert "../../../../../../../../dev/zero#_0" in line and "outside the model's folder" in line
    assert result.returncode == 1  # the field's type stays unresolved: D001


def test_an_href_to_a_device_allowed_outside_is_still_not_read(tmp_path: Path) -> None:
    model = _sample_with_href(tmp_path, "../../../../../../../../dev/zero#_0")
    result = earl("check", "--allow-outside", "/dev", str(model))
    line = _r004(result)
    assert "is a character device, not a regular file" in line


def test_an_href_to_a_fifo_beside_the_model_does_not_block(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "types.uml")
    model = _sample_with_href(tmp_path, "types.uml#_0")
    line = _r004(earl("check", str(model)))
    assert "types.uml#_0" in line and "is a FIFO (named pipe), not a regular file" in line


@pytest.mark.parametrize("kind", ["device", "fifo"])
def test_a_device_or_fifo_named_on_the_command_line_is_one_line_and_exit_2(kind: str, tmp_path: Path) -> None:
    if kind == "fifo":
        path = tmp_path / "model.uml"
        os.mkfifo(path)
    else:
        path = Path("/dev/zero")
    for command in (["check"], ["show"], ["stats"], ["gen", "-o", str(tmp_path / "out")]):
        result = earl(*command, str(path))
        assert result.returncode == 2
        errors = result.stderr.strip().splitlines()
        assert len(errors) == 1 and "not a regular file" in errors[0] and str(path) in errors[0], errors
    assert not (tmp_path / "out").exists()


def test_a_fifo_named_sysml_is_refused_too(tmp_path: Path) -> None:
    path = tmp_path / "model.sysml"
    os.mkfifo(path)
    result = earl("check", str(path))
    assert result.returncode == 2 and "is a FIFO (named pipe), not a regular file" in result.stderr


def _types_outside(tmp_path: Path) -> tuple[Path, Path]:
    """A model in repo/ whose field type is in ../elsewhere/types.uml (outside the repository)."""
    repo, elsewhere = tmp_path / "repo", tmp_path / "elsewhere"
    repo.mkdir()
    elsewhere.mkdir()
    (repo / ".git").mkdir()
    (elsewhere / "types.uml").write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<uml:Model xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" '
        'xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML" xmi:id="_types" name="Types">\n'
        '  <packagedElement xmi:type="uml:PrimitiveType" xmi:id="_real" name="Real"/>\n'
        '</uml:Model>\n', encoding="utf-8")
    return repo, _sample_with_href(repo, "../elsewhere/types.uml#_real")


def test_a_file_outside_the_repository_is_not_opened(tmp_path: Path) -> None:
    _, model = _types_outside(tmp_path)
    result = earl("check", str(model))
    line = _r004(result)
    assert "../elsewhere/types.uml#_real" in line and "outside the model's repository" in line
    assert " D001 " in result.stdout  # not read: the type stays unresolved


def test_allow_outside_on_the_command_line_or_in_the_configuration_reads_it(tmp_path: Path) -> None:
    repo, model = _types_outside(tmp_path)
    result = earl("check", "--allow-outside", str(tmp_path / "elsewhere"), str(model))
    assert result.returncode == 0 and " R004 " not in result.stdout, result.stdout
    (repo / "earl-m2t.toml").write_text('allow-outside = ["../elsewhere"]\n', encoding="utf-8")
    configured = earl("check", str(model), cwd=repo)
    assert configured.returncode == 0 and " R004 " not in configured.stdout, configured.stdout
    generated = earl("gen", str(model), "--target", "msg", "-o", str(tmp_path / "out"), cwd=repo)
    assert generated.returncode == 0, generated.stderr


def test_a_long_href_is_shortened_in_the_finding(tmp_path: Path) -> None:
    href = "x" * 30000 + ".uml#_0"
    line = _r004(earl("check", str(_sample_with_href(tmp_path, href))))
    assert len(line) < 1000 and "(30007 characters)" in line


# -- 2. no quadratic work on long names --------------------------------------------------------------


def test_a_dataype_name_of_200000_capitals_is_checked_and_reported(tmp_path: Path) -> None:
    text = SAMPLE.read_text(encoding="utf-8").replace('name="EncoderReading"', f'name="{"A" * 200000}"', 1)
    model = tmp_path / "long.uml"
    model.write_text(text, encoding="utf-8")
    result = earl("check", str(model))
    assert result.returncode == 1
    (line,) = [line for line in result.stdout.splitlines() if " D005 " in line]
    assert "(200011 characters)" in line and len(line) < 1000


# -- 3. the SysML v2 reader -------------------------------------------------------------------------


def _nested(depth: int) -> str:
    return "package M {\n" + "package P { " * (depth - 1) + "}" * (depth - 1) + "\n}\n"


def test_100_nested_packages_read(tmp_path: Path) -> None:
    model = tmp_path / "deep.sysml"
    model.write_text(_nested(100), encoding="utf-8")
    result = earl("check", str(model))
    assert result.returncode == 1 and " R003 " in result.stdout  # read; no EARL model in it


def test_nesting_beyond_200_levels_is_one_line_with_line_and_column(tmp_path: Path) -> None:
    model = tmp_path / "deeper.sysml"
    text = _nested(201)
    model.write_text(text, encoding="utf-8")
    second_line = text.splitlines()[1]
    column = [i for i, char in enumerate(second_line, 1) if char == "{"][199]  # the 201st '{' of the file
    result = earl("check", str(model))
    assert result.returncode == 2
    assert result.stderr.strip() == f"{model}:2:{column}: error: nested more than 200 levels deep ('{{'): not read"


@pytest.mark.parametrize(("old", "new", "mark", "what"), [
    ("part def ManipulatorAgent :> Agent", "part def Manipulator\x01Agent :> Agent", "\x01",
     "control character U+0001"),
    ("newData('manipulatorCommand/ib'.msg.jointPosSetpoint)",
     "newData('manipulatorCommand/ib'.msg.joint\x0bPosSetpoint)", "\x0b", "control character U+000B"),
    ("part def ManipulatorAgent :> Agent", "part def 'Manipulator\\bAgent' :> Agent", "\\b",
     "escape '\\b' gives a control character"),
])
def test_control_characters_are_refused_where_they_are_read(old: str, new: str, mark: str, what: str,
                                                             tmp_path: Path) -> None:
    text = SAMPLE_SYSML.read_text(encoding="utf-8")
    assert old in text
    broken = text.replace(old, new, 1)
    model = tmp_path / "model.sysml"
    model.write_text(broken, encoding="utf-8")
    offset = broken.index(new) + new.index(mark)
    line = broken.count("\n", 0, offset) + 1
    column = offset - broken.rfind("\n", 0, offset)
    result = earl("check", str(model))
    assert result.returncode == 2
    assert result.stderr.strip().startswith(f"{model}:{line}:{column}: error: {what}"), result.stderr


def test_text_that_is_not_utf8_is_one_line_with_its_position(tmp_path: Path) -> None:
    model = tmp_path / "model.sysml"
    model.write_bytes(b"package M {\n  part def \xff A;\n}\n")
    result = earl("check", str(model))
    assert result.returncode == 2 and result.stderr.startswith(f"{model}:2:12: error: ")


# -- 4. leftovers and late failures in gen -----------------------------------------------------------


def test_gen_removes_the_temporary_files_an_interrupted_run_left(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert earl("gen", str(SAMPLE), "--target", "msg", "-o", str(out)).returncode == 0
    folder = out / "pick_and_place_msgs" / "msg"
    stale = folder / ".EncoderReading.msg.k3j_x9a2.tmp"  # as an interrupted write leaves it
    stale.write_bytes(b"half a fi")
    notes = folder / ".notes.abcdefgh.tmp"  # not a file gen writes: not gen's to remove
    notes.write_bytes(b"mine")
    result = earl("gen", str(SAMPLE), "--target", "msg", "-o", str(out))
    assert result.returncode == 0
    assert not stale.exists() and notes.read_bytes() == b"mine"
    assert f"removed {stale} (a temporary file left by an interrupted run)" in result.stdout.splitlines()


def _long_pf(tmp_path: Path) -> Path:
    text = SAMPLE.read_text(encoding="utf-8").replace('name="planTask/pf"', f'name="{"p" * 5000}/pf"')
    model = tmp_path / "long.uml"
    model.write_text(text, encoding="utf-8")
    return model


def test_a_pf_of_5000_characters_is_reported_by_check_and_gen_writes_nothing(tmp_path: Path) -> None:
    model = _long_pf(tmp_path)
    checked = earl("check", str(model))
    assert checked.returncode == 1 and " D005 error: " in checked.stdout
    assert all(len(line) < 1000 for line in checked.stdout.splitlines())
    refused = earl("gen", str(model), "-o", str(tmp_path / "out"))
    assert refused.returncode == 1 and not (tmp_path / "out").exists()
    forced = earl("gen", str(model), "--force", "-o", str(tmp_path / "out"))
    assert forced.returncode == 2
    (error,) = forced.stderr.strip().splitlines()
    assert "more than the 255 file systems allow" in error and "nothing written" in error and len(error) < 1000
    assert forced.stdout == "" and not (tmp_path / "out").exists()


def test_a_gen_failing_part_way_says_what_it_wrote(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "generated").write_text("a file where gen needs a folder\n", encoding="utf-8")
    result = earl("gen", str(SAMPLE), "-o", str(out))
    assert result.returncode == 2
    wrote = result.stdout.splitlines()
    # files are written in path order: the source map and CMakeLists.txt come before generated/
    assert wrote == [f"wrote {out / '.earl-trace.json'}", f"wrote {out / 'CMakeLists.txt'}"]
    assert (out / "CMakeLists.txt").is_file() and (out / ".earl-trace.json").is_file()
    (error,) = result.stderr.strip().splitlines()
    assert "2 file(s) were written before it (listed above)" in error and "were not" in error


def test_windows_device_names_are_flagged(tmp_path: Path) -> None:
    text = SAMPLE.read_text(encoding="utf-8").replace('name="GripperStatus"', 'name="COM1"')
    model = tmp_path / "model.uml"
    model.write_text(text, encoding="utf-8")
    result = earl("check", str(model))
    (line,) = [line for line in result.stdout.splitlines() if " D006 " in line]
    assert "'COM1'" in line and "Windows" in line


def test_names_at_the_length_limit_generate_on_every_target(tmp_path: Path) -> None:
    """D005's limit is what every target can write: a model whose agent, subsystem, pf, dataType,
    field and buffer names are all 64 characters (snake_case-expanding ones) generates everywhere,
    no file or folder name over 255 bytes; one character more is D005."""
    longest = {"task/a": "tT" * 31 + "/a", "planTask/pf": "pP" * 30 + "p/pf", "GripperStatus": "Gs" * 32,
               "currentFingerPos": "cF" * 32, "encoder/ib": "eN" * 30 + "e/ib", "cs": "cS" * 32}
    text = SAMPLE.read_text(encoding="utf-8")
    for old, new in longest.items():
        assert f'name="{old}"' in text, old
        text = text.replace(f'name="{old}"', f'name="{new}"')
    model = tmp_path / "long.uml"
    model.write_text(text, encoding="utf-8")
    checked = earl("check", "--select", "D", str(model))
    assert checked.returncode == 0, checked.stdout
    for target in ("cpp", "msg", "ros", "ros2", "orocos", "markdown"):
        out = tmp_path / target
        result = earl("gen", str(model), "--force", "--target", target, "-o", str(out))
        assert result.returncode == 0, result.stderr
        names = [part for path in out.rglob("*") for part in path.relative_to(out).parts]
        assert max(len(name.encode("utf-8")) for name in names) <= 255
    over = tmp_path / "over.uml"
    over.write_text(text.replace(f'name="{longest["planTask/pf"]}"', f'name="x{longest["planTask/pf"]}"'),
                    encoding="utf-8")
    assert " D005 " in earl("check", "--select", "D", str(over)).stdout

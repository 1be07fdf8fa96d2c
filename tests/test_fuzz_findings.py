"""The reproductions of ``../shared/fuzz-findings/`` (an independent fuzzer's inputs, one per class
of failure) replayed: each command ends with a one-line answer and an exit code of its contract
(0-2; verify 0-3), never an internal error or a traceback, within its time bound.

A finding is listed here once its class is fixed at the root; the folder's README says what
each one is.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from xml.dom import minidom

import pytest

from earl_m2t.model.limits import MAX_OPERATORS
from earl_m2t.sysml2.limits import MAX_TEXT_BYTES
from tests.support.paths import ROOT, SHARED

FINDINGS = SHARED / "fuzz-findings"
SECONDS = 30  # the bound the fuzz campaign holds every run to
MEMORY_KB = 1 << 20  # 1 GiB of peak resident memory, the bound of the issue the findings came with

# (reproduction, command and its arguments after the model, exit codes its contract allows)
REPLAYS = [
    ("check-null-byte/model.uml", ["check"], {0, 1}),
    ("check-null-byte/model.uml", ["show"], {0}),
    ("minimal/n03_href_nul.uml", ["check"], {0, 1}),
    ("minimal/n03_href_nul.uml", ["convert", "--to", "sysml"], {0, 2}),
    ("verify-stopiteration/model.uml", ["verify"], {2}),
    ("verify-stopiteration/model.uml", ["verify", "--force"], {0, 1, 3}),
    ("minimal/n16_verify_initial_to_nowhere.uml", ["verify"], {2}),
    ("verify-invalid-promela/model.sysml", ["verify"], {2}),
    ("verify-invalid-promela/model.sysml", ["verify", "--force"], {2}),
    ("diff-recursion/model.sysml", ["check"], {2}),
    ("minimal/n04_not_chain_10000.sysml", ["check"], {2}),
    ("check-memory-sysml2-number/model.sysml", ["check"], {1}),
    ("minimal/n08_replication_2e31.sysml", ["check"], {1}),
    ("minimal/n08_replication_2e31.sysml", ["gen", "--target", "cpp"], {1}),
    ("check-clean-gen-fails/model.sysml", ["check"], {1}),
    ("check-clean-gen-fails/model.sysml", ["gen", "--target", "cpp"], {1}),
    ("gen-ros-memory-ea/model.ea.xml", ["check"], {1}),
    ("gen-ros-memory-ea/model.ea.xml", ["gen", "--target", "ros", "--force"], {0, 1}),
    ("minimal/n09_nested_any_k_8.uml", ["check"], {1}),
    ("minimal/n11_verify_timeout_any_k_6.uml", ["verify", "--timeout", "1"], {2}),
    ("minimal/n06_first_timeout_1e300.uml", ["check"], {1}),
    ("minimal/n06_first_timeout_1e300.uml", ["gen", "--target", "cpp", "--force"], {0}),
    ("minimal/n06b_first_timeout_9.3e9.uml", ["check"], {1}),
    # convert reads its text back before it writes it: the same model, or a refusal naming what differs
    ("convert-unreadable/model.uml", ["convert", "--to", "sysml"], {2}),
    ("convert-differs/model.uml", ["convert", "--to", "sysml"], {2}),
    ("minimal/n13_model_name_space.uml", ["convert", "--to", "sysml"], {0}),
    ("minimal/n05_package_name_with_space.sysml", ["check"], {0}),
    ("minimal/n01_sysml_65536_lines.sysml", ["check"], {0, 1}),
    ("minimal/n01_sysml_65536_lines.sysml", ["show"], {0}),
    ("minimal/n13b_model_name_newline.uml", ["convert", "--to", "sysml"], {2}),
    ("minimal/n13c_buffer_group_backslash.uml", ["convert", "--to", "sysml"], {2}),
    ("minimal/n04b_convert_not_chain.uml", ["convert", "--to", "sysml"], {0}),
    # a receive mode outside EARL's, generated with --force, is the latest value in every target
    ("gen-orocos-keyerror/model.uml", ["check"], {1}),
    ("gen-orocos-keyerror/model.uml", ["gen", "--target", "orocos", "--force"], {0}),
    ("minimal/n10_receive_dash.uml", ["gen", "--target", "orocos", "--force"], {0}),
    # 1.9 MB of SysML v2 text (10,000 predicates of a FABRIC package): past the reader's bound,
    # refused before the parser spends half a minute on it
    ("gen-orocos-fabric-timeout/imported.sysml", ["check"], {2}),
    ("gen-orocos-fabric-timeout/imported.sysml", ["gen", "--target", "orocos", "--force"], {2}),
]


@dataclass(frozen=True)
class Ran:
    returncode: int
    stdout: str
    stderr: str
    peak_kb: int  # the command's peak resident memory (its own rusage, from wait4)


def earl(*args: str | Path, cwd: Path) -> Ran:
    """The command line within SECONDS, and its peak resident memory."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        process = subprocess.Popen([sys.executable, "-m", "earl_m2t", *map(str, args)], stdout=out, stderr=err,
                                   cwd=cwd)
        deadline = time.monotonic() + SECONDS
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() > deadline:
                process.kill()
                os.wait4(process.pid, 0)
                process.returncode = -9
                raise subprocess.TimeoutExpired(process.args, SECONDS)
            time.sleep(0.02)
        process.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return Ran(process.returncode, out.read().decode(errors="replace"), err.read().decode(errors="replace"),
                   usage.ru_maxrss)


@pytest.mark.parametrize(("finding", "command", "allowed"), REPLAYS,
                         ids=[f"{finding}-{' '.join(command)}" for finding, command, _ in REPLAYS])
def test_the_reproduction_gets_an_answer_not_an_internal_error(finding: str, command: list[str], allowed: set[int],
                                                              tmp_path: Path) -> None:
    model = FINDINGS / finding
    assert model.is_file(), f"{model} is missing from ../shared"
    verb, *options = command
    extra = {"convert": ["-o", str(tmp_path / "out.sysml")], "gen": ["-o", str(tmp_path / "out")]}.get(verb, [])
    result = earl(verb, model, *options, *extra, cwd=ROOT)
    output = result.stdout + result.stderr
    assert result.returncode in allowed, output[-2000:]
    assert "internal error" not in output and "Traceback" not in output, output[-2000:]
    assert 0 < result.peak_kb < MEMORY_KB, f"peak resident memory {result.peak_kb} KiB"
    if verb == "convert":  # nothing written unless it reads back as the model it came from
        assert (tmp_path / "out.sysml").exists() == (result.returncode == 0), output
    if result.returncode == 2:  # refused: one line on stderr says why, naming the file
        assert result.stderr.strip(), output
        assert model.name in result.stderr or "earl-m2t:" in result.stderr, result.stderr


def test_the_diff_of_a_model_the_reader_refuses_is_one_line() -> None:
    sample = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"
    result = earl("diff", sample, FINDINGS / "diff-recursion" / "model.sysml", cwd=ROOT)
    assert result.returncode == 2, result.stdout + result.stderr
    assert "prefix operators in a row" in result.stderr and "internal error" not in result.stderr


def long_ec(operators: int, dialect: str) -> str:
    """The sample with one ec of ``operators`` disjunctions (R6: the parse cost grows faster than the text)."""
    if dialect == "sysml":
        text = (ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml").read_text()
        return text.replace("constraint ec { false }", "constraint ec { " + "false or " * operators + "false }", 1)
    text = (ROOT / "samples" / "pick_and_place" / "pick_and_place.uml").read_text()
    return text.replace("<body>FALSE</body>", "<body>" + "FALSE ∨ " * operators + "FALSE</body>", 1)


@pytest.mark.parametrize(("dialect", "refused_with"), [("sysml", 2), ("uml", 1)])
def test_an_expression_past_the_operator_bound_is_refused_at_once(dialect: str, refused_with: int,
                                                                 tmp_path: Path) -> None:
    """R6: SysML v2 text is refused before parsing (exit 2); a predicate-language body is a
    condition the checker reports (exit 1); both in well under a second of parsing."""
    model = tmp_path / f"long.{dialect}"
    model.write_text(long_ec(MAX_OPERATORS + 1, dialect))
    result = earl("check", model, cwd=ROOT)
    assert result.returncode == refused_with, result.stdout + result.stderr
    assert f"more than {MAX_OPERATORS} operators" in result.stdout + result.stderr
    assert f"{model}:" in result.stdout + result.stderr  # where: the file and its line


def test_an_expression_within_the_operator_bound_is_read(tmp_path: Path) -> None:
    model = tmp_path / "long.sysml"
    model.write_text(long_ec(MAX_OPERATORS - 1, "sysml"))
    result = earl("check", model, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr


def test_sysml_text_past_the_size_bound_is_refused_at_once_in_one_line_naming_the_file(tmp_path: Path) -> None:
    """The parser reads some 70 KB a second: a text over MAX_TEXT_BYTES is refused unparsed."""
    text = (ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml").read_text(encoding="utf-8")
    model = tmp_path / "large.sysml"
    padding = MAX_TEXT_BYTES + 1 - len(text.encode("utf-8"))
    model.write_text(text + "/" * padding, encoding="utf-8")  # a comment line of slashes
    assert model.stat().st_size == MAX_TEXT_BYTES + 1
    for command in (["check"], ["gen", "--target", "cpp", "-o", str(tmp_path / "out")], ["show"]):
        result = earl(command[0], model, *command[1:], cwd=ROOT)
        assert result.returncode == 2, result.stdout + result.stderr
        refused = [line for line in result.stderr.splitlines() if "more than the 1,048,576 (1 MiB)" in line]
        assert len(refused) == 1 and f"{model}: error: SysML v2 text of 1,048,577 bytes" in refused[0], result.stderr
    model.write_text(text + "/" * (padding - 1), encoding="utf-8")  # at the bound: read (comment skipped quickly)
    assert model.stat().st_size == MAX_TEXT_BYTES
    assert "1 MiB" not in earl("show", model, cwd=ROOT).stderr


def test_import_fabric_writes_no_text_past_the_size_bound(tmp_path: Path) -> None:
    """A FABRIC package of 10,000 predicates makes 1.9 MB of SysML v2 text that no command would
    read back: import fabric says so in one line and writes nothing."""
    package = FINDINGS / "gen-orocos-fabric-timeout" / "fab" / "velma_task_cs_ros_interface"
    target = tmp_path / "imported.sysml"
    result = earl("import", "fabric", package, "-o", target, cwd=ROOT)
    assert result.returncode == 2, result.stdout + result.stderr
    [line] = result.stderr.splitlines()
    assert line.startswith(f"earl-m2t: import fabric: {target}: the model would be SysML v2 text of 1,9"), line
    assert line.endswith(" bytes, more than the 1,048,576 (1 MiB) the reader parses: nothing written"), line
    assert not target.exists()


def test_a_name_with_a_double_hyphen_keeps_the_fabric_files_well_formed(tmp_path: Path) -> None:
    """R8: a block named ``Gripper--Control`` reaches the XML comments of the FABRIC files, where
    XML forbids ``--``: FABRIC's own parser must still read every spec, and every configuration
    must be well-formed."""
    result = earl("gen", FINDINGS / "minimal" / "n02_double_hyphen_block.sysml", "--target", "orocos",
                  "-o", tmp_path, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    specs = sorted(tmp_path.glob("fabric/*/spec/subsystem.xml"))
    parsed = subprocess.run([sys.executable, str(SHARED / "fabric" / "run_parser.py"), *map(str, specs)],
                            capture_output=True, text=True, timeout=SECONDS)
    assert parsed.returncode == 0 and f"ok={len(specs)}" in parsed.stdout, parsed.stdout + parsed.stderr
    assert "Gripper- -Control" in (tmp_path / "fabric" / "grip_a_cs" / "spec" / "subsystem.xml").read_text()
    for configuration in tmp_path.glob("fabric/*/config/*.xml"):
        minidom.parse(str(configuration))  # raises on malformed XML


def test_trace_of_a_corrupt_source_map_is_one_line(tmp_path: Path) -> None:
    """R16: an entry of the wrong shape, and a map of 200,000 nested brackets."""
    result = earl("trace", "generated/a.hpp:1", cwd=FINDINGS / "minimal" / "n14_trace")
    assert result.returncode == 2 and "is malformed" in result.stderr, result.stdout + result.stderr
    (tmp_path / "generated").mkdir()
    (tmp_path / "generated" / "a.hpp").write_text("int a;\n")
    (tmp_path / ".earl-trace.json").write_text("[" * 200_000)
    result = earl("trace", "generated/a.hpp:1", cwd=tmp_path)
    assert result.returncode == 2 and "not a source map" in result.stderr, result.stdout + result.stderr
    assert "Traceback" not in result.stderr


def test_a_name_with_a_line_break_stays_inside_the_user_files_comment(tmp_path: Path) -> None:
    """R9: a pf named ``jointMove⏎#error INJECTED⏎/pf``, generated with --force: the name is
    shown on the header's comment line, never as a line of code."""
    out = tmp_path / "out"
    result = earl("gen", FINDINGS / "minimal" / "n12_pf_name_newline.uml", "--target", "cpp", "--force", "-o", out,
                  cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    injected = [path for path in out.rglob("*.hpp") if any(line.startswith("#error")
                                                             for line in path.read_text().splitlines())]
    assert injected == []
    (user_file,) = out.glob("user/manip_a/cs/jointMove*_pf.hpp")
    assert user_file.read_text().splitlines()[0] == "// earl-m2t user file: pf manip/a.cs.jointMove #error INJECTED /pf"


def test_verify_of_a_model_whose_subsystems_never_move_hands_spin_a_valid_specification() -> None:
    """Every subsystem of the guide's route example is left out (no iteration changes what the
    checks observe): the specification still has a process, and SPIN reads it."""
    result = earl("verify", ROOT / "tests" / "fixtures" / "guide" / "route-stereotype.uml", cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "spin -a failed" not in result.stderr and "no deadlock" in result.stdout

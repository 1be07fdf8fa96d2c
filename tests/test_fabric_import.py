"""earl-m2t import fabric: Velma's real FABRIC packages (../shared/fabric/examples) import, check
without errors, and regenerate through gen --target orocos into specs that FABRIC's own parser
accepts and that equal the originals element by element (tests/support/fabric_compare.py). Bad
FABRIC input is one line with file and line, exit 2."""

from __future__ import annotations

import shutil
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

from earl_m2t.fabric import packages_to_model, read_package
from earl_m2t.gen import render
from tests.support import fabric
from tests.support.fabric_compare import differences

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ["velma_system/velma_core_ve_body", "velma_system/velma_task_cs_ros_interface",
            "velma_pred_ctrl_interface"]


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)


def folders() -> list[Path]:
    found = [fabric.EXAMPLES / p for p in PACKAGES]
    if not all((f / "spec" / "subsystem.xml").is_file() for f in found):
        pytest.skip("FABRIC's examples (../shared/fabric/examples) are not beside the checkout")
    return found


def regenerated_specs(files: dict[str, bytes], folder: Path) -> dict[str, Path]:
    """The specs among generated files, written to ``folder``, by package folder name."""
    specs: dict[str, Path] = {}
    for name, content in files.items():
        if name.startswith("fabric/") and name.endswith("/spec/subsystem.xml"):
            path = folder / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(content)
            specs[name.split("/")[1]] = path
    return specs


def original_of(package: str, specs: dict[str, Path]) -> Path:
    """The regenerated spec of an imported package: its agent's control subsystem is ``cs``."""
    return specs[package] if package in specs else specs[f"{package}_cs"]


def test_the_examples_regenerate_equal_from_the_imported_model(tmp_path: Path) -> None:
    packages = [read_package(f) for f in folders()]
    model, notes = packages_to_model(packages, "velma")
    assert len(notes) == 1 and notes[0].startswith("velma_core_ve_body:")
    specs = regenerated_specs(render(model, "orocos").generated, tmp_path)
    assert len(specs) == 3
    for folder in folders():
        original = fabric.parse_spec(folder / "spec" / "subsystem.xml")
        regenerated = fabric.parse_spec(original_of(folder.name, specs))
        assert differences(original, regenerated) == [], folder.name


@pytest.fixture(scope="module")
def imported(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("import")
    result = earl("import", "fabric", *map(str, folders()), "-o", str(folder / "velma.sysml"))
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"wrote {folder / 'velma.sysml'}"
    return folder / "velma.sysml"


def test_the_imported_model_checks_without_errors(imported: Path) -> None:
    result = earl("check", str(imported))
    assert result.returncode == 0, result.stdout + result.stderr
    assert " 0 error(s)" in result.stdout


@pytest.fixture(scope="module")
def regenerated(imported: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """gen --target orocos of the written model: its specs by package folder name."""
    folder = tmp_path_factory.mktemp("regenerated")
    result = earl("gen", str(imported), "--target", "orocos", "-o", str(folder))
    assert result.returncode == 0, result.stderr
    specs = {p.parent.parent.name: p for p in folder.glob("fabric/*/spec/subsystem.xml")}
    assert len(specs) == 3
    return specs


def test_the_written_model_regenerates_specs_and_configurations_fabric_accepts(
        regenerated: dict[str, Path], tmp_path: Path) -> None:
    for n, path in enumerate(sorted(regenerated.values())):
        spec = fabric.parse_spec(path)
        for config in path.parent.parent.glob("config/*.xml"):
            assert fabric.configuration_problems(config, spec) == [], config
        if shutil.which("g++") is not None:
            (tmp_path / str(n)).mkdir()
            compiled = fabric.compile_conditions(spec, tmp_path / str(n))
            assert compiled.returncode == 0, compiled.stderr


def test_the_written_model_regenerates_specs_equal_to_the_originals(regenerated: dict[str, Path]) -> None:
    for folder in folders():
        original = fabric.parse_spec(folder / "spec" / "subsystem.xml")
        regenerated_spec = fabric.parse_spec(original_of(folder.name, regenerated))
        assert differences(original, regenerated_spec) == [], folder.name


def test_importing_again_writes_nothing_and_keeps_an_edited_model(imported: Path) -> None:
    again = earl("import", "fabric", *map(str, folders()), "-o", str(imported))
    assert again.returncode == 0 and again.stdout == f"unchanged {imported}\n"
    imported.write_text(imported.read_text(encoding="utf-8") + "// my note\n", encoding="utf-8")
    kept = earl("import", "fabric", *map(str, folders()), "-o", str(imported))
    assert kept.returncode == 1 and "--force" in kept.stderr
    assert imported.read_text(encoding="utf-8").endswith("// my note\n")


@pytest.mark.parametrize(("file", "old", "new", "message"), [
    ("spec/subsystem.xml", 'min_period_sim="0.001" ', "", "<buffer_group> must have the attribute 'min_period_sim'"),
    ("spec/subsystem.xml", '<obligatory name="st" />', '<obligatory name="status" />',
     "names 'status', which is no <in> buffer"),
    ("spec/subsystem.xml", 'stop_cond="FALSE"', 'stop_cond="FALSE and"',
     "behavior 'normal' stop_cond: the condition ends too early"),
    ("spec/subsystem.xml", 'err_cond="FALSE"', 'err_cond="IN_ERROR)"', "unexpected ')'"),
    ("spec/subsystem.xml", '<states initial="normal">', '<states initial="start">',
     "the initial state 'start' is not a <state>"),
    ("spec/subsystem.xml", 'type="velma_core_cs_task_cs_msgs::Status"', 'type="Status"', "is not 'package::Message'"),
    ("spec/subsystem.xml", "</subsystem_definition>", "", "not well-formed XML"),
    ("spec/subsystem.xml", 'use_sim_clock="true"', 'use_sim_clock="yes"',
     "<simulation> use_sim_clock='yes' is neither true nor false"),
    ("spec/subsystem.xml", 'use_ros_sim_clock="true" ', "", "<simulation> must have the attribute 'use_ros_sim_clock'"),
    ("spec/subsystem.xml", 'stop_cond="FALSE"', 'stop_cond="ready"',
     "'ready' is not a <predicate> of the subsystem"),
    ("spec/subsystem.xml", 'stop_cond="FALSE"', f'stop_cond="{"(" * 20_000}FALSE{")" * 20_000}"',
     "behavior 'normal' stop_cond: nested more than 200 levels deep (parentheses and 'not')"),
    ("spec/subsystem.xml", 'stop_cond="FALSE"', f'stop_cond="{"not " * 201}FALSE"',
     "nested more than 200 levels deep (parentheses and 'not')"),
    ("spec/subsystem.xml", 'stop_cond="FALSE"', f'stop_cond="FALSE{" or FALSE" * 10_001}"',
     "10,001 operators, more than the 10,000 a condition may have"),
    ("config/velma_pred_ctrl_interface.xml", '<io_buffer alias="st" name="velma_core_st2" />',
     '<io_buffer alias="st" />', "<io_buffer> must have the attribute 'name'"),
    ("config/velma_pred_ctrl_interface.xml", "</subsystem_configuration>", "", "not well-formed XML"),
])
def test_bad_fabric_input_is_one_line_with_file_and_line(tmp_path: Path, file: str, old: str, new: str,
                                                        message: str) -> None:
    source = next(f for f in folders() if f.name == "velma_pred_ctrl_interface")
    package = tmp_path / "broken"
    shutil.copytree(source, package)
    spec = package / file
    text = spec.read_text(encoding="utf-8")
    assert old in text
    spec.write_text(text.replace(old, new, 1), encoding="utf-8")
    result = earl("import", "fabric", str(package), "-o", str(tmp_path / "model.sysml"))
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr
    assert lines[0].startswith(f"{spec}:") and message in lines[0], lines[0]
    line = int(lines[0].split(":")[1])
    assert line > 0
    assert not (tmp_path / "model.sysml").exists()


def test_a_condition_nested_as_deep_as_allowed_is_imported(tmp_path: Path) -> None:
    source = next(f for f in folders() if f.name == "velma_pred_ctrl_interface")
    package = tmp_path / "deep"
    shutil.copytree(source, package)
    spec = package / "spec" / "subsystem.xml"
    deep = "not (" * 100 + "FALSE" + ")" * 100
    spec.write_text(spec.read_text(encoding="utf-8").replace('stop_cond="FALSE"', f'stop_cond="{deep}"', 1),
                    encoding="utf-8")
    result = earl("import", "fabric", str(package), "-o", str(tmp_path / "model.sysml"))
    assert result.returncode == 0, result.stderr
    assert earl("check", str(tmp_path / "model.sysml")).returncode == 0


def test_packages_on_one_ipc_channel_are_linked(tmp_path: Path) -> None:
    """An output and another package's input with the same <io_buffer name> become a link, and the
    regenerated configurations give both ends one channel."""
    source = next(f for f in folders() if f.name == "velma_task_cs_ros_interface")
    echo = tmp_path / "velma_echo_cs_ros_interface"
    shutil.copytree(source, echo)
    config = echo / "config" / "velma_task_cs_ros_interface.xml"
    text = config.read_text(encoding="utf-8")
    assert '<io_buffer alias="st" name="velma_core_st" />' in text
    config.write_text(text.replace('<io_buffer alias="st" name="velma_core_st" />',
                                   '<io_buffer alias="st" name="velma_core_cmd" />'), encoding="utf-8")
    spec = echo / "spec" / "subsystem.xml"
    spec.write_text(spec.read_text(encoding="utf-8").replace(
        'alias="st"      type="velma_core_cs_task_cs_msgs::Status"',
        'alias="st"      type="velma_core_cs_task_cs_msgs::Command"'), encoding="utf-8")
    model, _ = packages_to_model([read_package(source), read_package(echo)], "pair")
    assert [(link.source, link.target, link.scope) for link in model.links] == [
        ("velma_task.cs_ros_interface.cmd/ob", "velma_echo.cs_ros_interface.st/ib", "system")]
    channels: dict[str, dict[str, str]] = {}
    for name, content in render(model, "orocos").generated.items():
        if "/config/" in name:
            root = ElementTree.fromstring(content)
            channels[name.split("/")[1]] = {b.get("alias", ""): b.get("name", "") for b in root.iter("io_buffer")}
    assert channels["velma_echo_cs_ros_interface"]["st"] == channels["velma_task_cs_ros_interface"]["cmd"]

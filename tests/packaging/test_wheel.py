"""The wheel carries the data folders: built, installed in a fresh venv, run outside the checkout."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"


@pytest.fixture(scope="module")
def installed_wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    work = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(work / "dist"),
         str(ROOT)],
        check=True,
    )
    wheels = list((work / "dist").glob("earl_m2t-*.whl"))
    assert len(wheels) == 1
    env_dir = work / "venv"
    # a fresh venv: the wheel's declared dependencies are installed from the package index
    venv.EnvBuilder(with_pip=True).create(env_dir)
    python = env_dir / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "-q", str(wheels[0])], check=True)
    return env_dir


def _run(env_dir: Path, *args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH",)}
    return subprocess.run([str(env_dir / "bin" / "earl-m2t"), *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


def test_the_installed_wheel_checks_the_sample_from_outside_the_checkout(installed_wheel: Path, tmp_path: Path) -> None:
    model = tmp_path / "model.uml"
    shutil.copy(SAMPLE, model)
    result = _run(installed_wheel, "check", str(model), cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "0 error(s), 0 warning(s)" in result.stdout


def test_the_installed_wheel_finds_its_data_inside_the_package(installed_wheel: Path, tmp_path: Path) -> None:
    python = installed_wheel / "bin" / "python"
    probe = ("import earl_m2t, earl_m2t.resources as r; "
             "print(earl_m2t.__file__); print(r.data_dir('metamodel')); print(r.data_dir('profiles'))")
    result = subprocess.run([str(python), "-c", probe], cwd=tmp_path, capture_output=True, text=True, check=True)
    package_file, metamodel, profiles = result.stdout.split()
    assert str(ROOT) not in package_file
    assert metamodel.endswith(os.path.join("earl_m2t", "_data", "metamodel"))
    assert (Path(profiles) / "earl.sysml").is_file()
    rules = _run(installed_wheel, "rules", "B005", cwd=tmp_path)
    assert rules.returncode == 0 and "B005" in rules.stdout


def test_the_installed_wheel_carries_the_bytecode_of_every_module(installed_wheel: Path, tmp_path: Path) -> None:
    """pip compiles the modules as it installs the wheel, so that a CI job running with
    PYTHONDONTWRITEBYTECODE=1 does not compile them again on every start."""
    python = installed_wheel / "bin" / "python"
    probe = ("import importlib.util, os, pathlib, earl_m2t; "
             "root = pathlib.Path(earl_m2t.__file__).parent; "
             "modules = sorted(root.rglob('*.py')); "
             "print(len(modules)); "
             "print(*[m.relative_to(root) for m in modules "
             "if not os.path.isfile(importlib.util.cache_from_source(str(m)))])")
    result = subprocess.run([str(python), "-c", probe], cwd=tmp_path, capture_output=True, text=True, check=True)
    count, missing = result.stdout.split("\n", 1)
    assert int(count) > 100
    assert missing.strip() == ""

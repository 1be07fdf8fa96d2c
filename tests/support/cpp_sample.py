"""Building a sample's C++ as a user does: its shipped user code copied into an empty output
folder, `gen --target cpp` over it (which must create no stub and find no orphan), and the
CMake project built with warnings as errors."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from tests.support import build_cache


def run(*command: str | Path, timeout: int = 300) -> str:
    """stdout of ``command``; a failure fails the test with both streams."""
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=timeout)
    assert result.returncode == 0, f"{command[0]} failed:\n{result.stdout}\n{result.stderr}"
    return result.stdout


def generate_with_user_code(model: Path, user: Path, out: Path) -> Path:
    """``out`` holding ``user`` as ``out/user`` and what gen writes for ``model`` around it."""
    shutil.copytree(user, out / "user")
    gen = run(sys.executable, "-m", "earl_m2t", "gen", model, "--target", "cpp", "-o", out)
    assert not [line for line in gen.splitlines() if line.startswith(("created ", "orphaned "))], gen
    return out


def cmake_project(source: Path, *flags: str, target: str | None = None) -> Path:
    """The build folder of the CMake project in ``source`` (Release, warnings as errors, ``flags``
    added; every target, or ``target`` alone), built once per content (tests/support/build_cache.py)."""
    configure = ["-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_CXX_COMPILER=g++",
                 "-DCMAKE_CXX_FLAGS=" + " ".join(("-Wall", "-Wextra", "-Werror", *flags))]
    targets = ["--target", target] if target else []

    def build(folder: Path) -> None:
        run("cmake", "-S", folder / build_cache.SOURCE, "-B", folder / "build", *configure)
        run("cmake", "--build", folder / "build", "-j", "2", *targets)

    return build_cache.built(f"cpp-{target or 'all'}", source, build, ["cmake", *configure, *targets]) / "build"


def cmake_build(source: Path, target: str, *flags: str) -> Path:
    """The executable ``target`` of the CMake project in ``source``, built as :func:`cmake_project` builds."""
    return cmake_project(source, *flags, target=target) / target

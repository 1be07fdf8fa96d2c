"""The code keeps the ruff configuration of pyproject.toml ([tool.ruff])."""

from __future__ import annotations

import subprocess
import sys

from tests.support.paths import ROOT


def test_ruff_finds_nothing() -> None:
    result = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache", "earl_m2t", "tests", "bench",
                             "scripts"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr

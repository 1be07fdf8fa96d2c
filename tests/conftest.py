"""Fixtures shared by the whole suite: the reference sample and the script that writes it; every
compile of the suite goes through ccache when it is installed (tests/support/compiler_cache.py).

The checkout is importable (``tests.support``) through pyproject's ``pythonpath``: no test
module changes ``sys.path``."""

from __future__ import annotations

import importlib.util
import os
import signal
from pathlib import Path
from types import ModuleType

import pytest

from tests.support import compiler_cache
from tests.support.paths import ROOT, SAMPLE


def pytest_configure(config: pytest.Config) -> None:
    compiler_cache.enable(os.environ)
    # A run started in the background of a non-interactive shell (`./dev test &`, many CI
    # runners) ignores SIGINT, and every program a test starts inherits that: the graceful stop
    # of tests/support/load.py (SIGINT, then SIGKILL after 5 s) would wait out its 5 s on each
    # run of a program that does not catch SIGINT itself (a generated C++ system). The handler
    # set here is reset to the default in every program started.
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under pytest-xdist (``--dist loadgroup``, what ``./dev test`` runs the tests that are
    not ``loaded`` with), each module's tests stay together on one worker, so that its module
    fixtures run once; a module with an ``xdist_group`` of its own shares a worker with the
    other modules of that group (the ROS 2 modules: two launches at once could meet on one
    ROS domain). Runs before xdist reads the groups."""
    for item in items:
        if item.get_closest_marker("xdist_group") is None:
            item.add_marker(pytest.mark.xdist_group(item.path.relative_to(ROOT).as_posix()))


@pytest.fixture(scope="session")
def sample_path() -> Path:
    return SAMPLE


@pytest.fixture(scope="session")
def sample_bytes() -> bytes:
    return SAMPLE.read_bytes()


@pytest.fixture(scope="session")
def make_sample() -> ModuleType:
    """``scripts/make_sample.py`` as a module (``build(stereotypes=...)`` writes the sample)."""
    spec = importlib.util.spec_from_file_location("make_sample", ROOT / "scripts" / "make_sample.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

"""Compiles of the suite go through ccache when it is installed (``./dev test`` installs it).

The suite compiles the same generated code on every run: the C++ target with CMake, the ROS
packages with catkin_make and colcon, the Orocos components. CMake (3.17 and newer) takes
``CMAKE_<LANG>_COMPILER_LAUNCHER`` from the environment, so one setting reaches every build,
catkin's and colcon's included. The cache key is the preprocessed source and the flags, so a
changed header or flag compiles again: what is built is what a plain compile builds. Every build
folder of the suite is a fresh temporary one; the base directory ``/`` makes ccache key its
paths relative to the build folder, so a rerun in another temporary folder still hits.

The cache lives in ``${XDG_CACHE_HOME:-~/.cache}/earl-m2t/ccache``, at most ``MAX_SIZE``.
Settings already in the environment win, and ``EARL_CCACHE=0`` turns it off."""

from __future__ import annotations

import os
import shutil
from collections.abc import MutableMapping
from pathlib import Path

MAX_SIZE = "3G"


def cache_folder() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "earl-m2t" / "ccache"


def enable(environment: MutableMapping[str, str]) -> bool:
    """Adds the settings to ``environment`` (each only when unset); False without ccache."""
    if environment.get("EARL_CCACHE") == "0" or shutil.which("ccache") is None:
        return False
    for language in ("C", "CXX"):
        environment.setdefault(f"CMAKE_{language}_COMPILER_LAUNCHER", "ccache")
    environment.setdefault("CCACHE_DIR", str(cache_folder()))
    environment.setdefault("CCACHE_BASEDIR", "/")
    environment.setdefault("CCACHE_NOHASHDIR", "1")
    environment.setdefault("CCACHE_MAXSIZE", MAX_SIZE)
    return True

"""Where the tests find a ROS 2 Jazzy, building it once when needed.

The prefix is built by ``../shared/vendor/ros2/build.sh`` (pinned PyPI wheels in a venv, plus the
vendored rclcpp, rclcpp_components, rclcpp_lifecycle, launch, launch_ros and ros2cli sources built
with colcon) into the build cache ``${XDG_CACHE_HOME:-~/.cache}/earl-m2t/ros2/<key>``, where
``<key>`` hashes ``requirements.lock``, the tarballs and ``build.sh`` with the compiler and Python
versions. ``ROS2_JAZZY_PREFIX`` names a prefix built by that script elsewhere instead.
``ensure`` builds it when it is missing (``./dev test`` runs it before the tests); the build needs
PyPI once. A failed build leaves ``<key>.failed`` with the log's tail, which the ROS 2 tests report
as their failure instead of skipping. The prefix is not relocatable: it is built where it is used.

Run as a script (standard library only, so it works before the test environment exists):
``python3 tests/support/ros2.py ensure`` prints the prefix, or the failure, and what it did.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
VENDOR = ROOT.parent / "shared" / "vendor" / "ros2"
LOG_TAIL_LINES = 40
# What build.sh's README gives a workspace built on top of the prefix (the `Use` section).
COLCON_CMAKE_ARGS = ("-DCMAKE_BUILD_TYPE=None", "-DCMAKE_C_FLAGS=-O0 -g0", "-DCMAKE_CXX_FLAGS=-O0 -g0",
                     "-DBUILD_TESTING=OFF", "-DCMAKE_EXE_LINKER_FLAGS=-Wl,--as-needed,--allow-shlib-undefined",
                     "-DCMAKE_SHARED_LINKER_FLAGS=-Wl,--as-needed")


LAUNCH_DESCRIPTION = Path(__file__).with_name("ros2_launch_description.py")
# a line of a generated parameter file: a node's fully qualified name, or a parameter and its value
PARAMETER_FILE_LINE = re.compile(r"^(?:(/[\w/]+):|    (\w+): (.+))$")


class Ros2Unavailable(Exception):
    """No usable prefix, and none can be built here; the message says why in one line."""


class Ros2BuildFailed(Exception):
    """The vendored sources did not build; the message holds the log's tail."""


@dataclass(frozen=True)
class Installation:
    prefix: Path
    origin: str  # "ROS2_JAZZY_PREFIX" or "cache"

    @property
    def env_script(self) -> Path:
        return self.prefix / "env.sh"

    @property
    def python(self) -> Path:
        return self.prefix / "venv" / "bin" / "python"

    def environment(self, *workspaces: Path, domain_id: int | None = None) -> dict[str, str]:
        """os.environ with env.sh sourced, then each workspace's install/setup.sh, as a dict."""
        script = f'. "{self.env_script}"'
        for workspace in workspaces:
            script += f' && . "{workspace / "install" / "setup.sh"}"'
        script += " && env -0"
        result = subprocess.run(["bash", "-c", script], capture_output=True, check=True)
        env = dict(item.split("=", 1) for item in result.stdout.decode().split("\0") if "=" in item)
        if domain_id is not None:
            env["ROS_DOMAIN_ID"] = str(domain_id)
        return env

    def colcon_build(self, workspace: Path, *cxx_flags: str) -> Path:
        """``colcon build`` of ``workspace`` (its src/), ``cxx_flags`` added to the C++ flags, once
        per content (tests/support/build_cache.py): the built workspace, holding src/, build/ and
        install/. A failure fails the calling test with colcon's output."""
        from tests.support import build_cache

        command = self.colcon_build_command(*cxx_flags)

        def build(folder: Path) -> None:
            result = subprocess.run(command, cwd=folder, capture_output=True, text=True, env=self.environment(),
                                    timeout=1800)
            assert result.returncode == 0, f"colcon build failed:\n{result.stdout[-6000:]}\n{result.stderr[-6000:]}"

        return build_cache.built("colcon", workspace / "src", build, [str(self.prefix), *command])

    def launch_description(self, workspace: Path, launch_file: Path, **arguments: str) -> list[dict[str, Any]]:
        """The nodes ``launch_file`` would start with ``name:=value`` arguments, as launch's own
        loader evaluates it in ``workspace``'s environment, without starting them
        (tests/support/ros2_launch_description.py)."""
        request = {"launch_file": str(launch_file), "arguments": arguments}
        result = subprocess.run([str(self.python), str(LAUNCH_DESCRIPTION)], input=json.dumps(request),
                                capture_output=True, text=True, env=self.environment(workspace), timeout=120)
        assert result.returncode == 0, f"{launch_file.name} {arguments}: {result.stderr[-3000:]}"
        nodes: list[dict[str, Any]] = json.loads(result.stdout)["nodes"]
        return nodes

    def colcon_build_command(self, *cxx_flags: str) -> list[str]:
        """colcon build with the flags of the README's `Use` section, ``cxx_flags`` added to its C++ flags."""
        cmake_args = [f"{argument} {' '.join(cxx_flags)}" if cxx_flags and argument.startswith("-DCMAKE_CXX_FLAGS=")
                      else argument for argument in COLCON_CMAKE_ARGS]
        return ["colcon", "build", "--event-handlers", "console_direct-", "console_stderr+",
                "--cmake-args", *cmake_args, f"-DPython3_EXECUTABLE={self.python}"]


def generated_parameters(path: Path) -> dict[str, dict[str, Any]]:
    """A parameter file gen wrote (``config/<agent>.yaml``), by node: the values of its
    ``ros__parameters``. Reads only the layout gen writes (each scalar one JSON value), so that
    the tests need no YAML library; launch_ros reads it with PyYAML and the nodes with rcl."""
    return parameters_of_text(path.read_text(encoding="utf-8"), path.name)


def parameters_of_text(text: str, name: str) -> dict[str, dict[str, Any]]:
    """:func:`generated_parameters` of a parameter file's text (``name`` for the messages)."""
    nodes: dict[str, dict[str, Any]] = {}
    for line in text.splitlines():
        found = PARAMETER_FILE_LINE.match(line)
        if found and found.group(1):
            nodes[found.group(1)] = {}
        elif found:
            nodes[next(reversed(nodes))][found.group(2)] = json.loads(found.group(3))
        else:
            assert line.startswith("#") or line == "  ros__parameters:", f"{name}: {line!r}"
    return nodes


def is_usable(prefix: Path) -> bool:
    """build.sh writes env.sh last: its presence means a complete run."""
    return (prefix / "env.sh").is_file() and (prefix / "venv" / "bin" / "python").is_file()


def cache_root() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "earl-m2t" / "ros2"


def vendored_files() -> list[Path]:
    return sorted([*VENDOR.glob("*.tar.gz"), VENDOR / "build.sh", VENDOR / "requirements.lock"])


def toolchain_versions() -> str:
    """What a cached build depends on besides its sources: g++ (its first line) and /usr/bin/python3."""
    compiler = subprocess.run(["g++", "--version"], capture_output=True, text=True).stdout.splitlines()[0] \
        if shutil.which("g++") else "none"
    python = "none"
    if Path("/usr/bin/python3").is_file():
        python = subprocess.run(["/usr/bin/python3", "-c", "import sys; print(sys.version.split()[0])"],
                                capture_output=True, text=True).stdout.strip()
    return f"{compiler}; python {python}"


def cache_key() -> str:
    digest = hashlib.sha256()
    for file in vendored_files():
        digest.update(file.name.encode() + b"\0" + hashlib.sha256(file.read_bytes()).digest())
    digest.update(toolchain_versions().encode())
    return digest.hexdigest()[:16]


def cached_prefix() -> Path:
    return cache_root() / cache_key()


def failure_marker(prefix: Path) -> Path:
    return prefix.with_name(prefix.name + ".failed")


def complete_stamp(prefix: Path) -> Path:
    return prefix / ".earl-m2t-complete"


def find() -> Installation | None:
    """A usable prefix that is already there, without building anything."""
    explicit = os.environ.get("ROS2_JAZZY_PREFIX")
    if explicit:
        if not is_usable(Path(explicit)):
            raise Ros2Unavailable(f"ROS2_JAZZY_PREFIX={explicit} holds no env.sh or venv/ (a prefix "
                                  "built by ../shared/vendor/ros2/build.sh)")
        return Installation(Path(explicit), "ROS2_JAZZY_PREFIX")
    if VENDOR.is_dir():
        prefix = cached_prefix()
        if complete_stamp(prefix).is_file() and is_usable(prefix):
            return Installation(prefix, "cache")
    return None


def installation() -> Installation:
    """What the ROS 2 tests run against; raises when there is none (never builds)."""
    found = find()
    if found is not None:
        return found
    if not VENDOR.is_dir():
        raise Ros2Unavailable("no ROS 2 Jazzy prefix and no ../shared/vendor/ros2 to build one from "
                              "(set ROS2_JAZZY_PREFIX)")
    marker = failure_marker(cached_prefix())
    if marker.is_file():
        raise Ros2BuildFailed(marker.read_text())
    raise Ros2BuildFailed(f"ROS 2 Jazzy not built yet into {cached_prefix()}: run ./dev test, or "
                          "python3 tests/support/ros2.py ensure")


def log(message: str) -> None:
    print(f"earl-m2t: {message}", file=sys.stderr, flush=True)


def build(prefix: Path) -> None:
    """Build the vendored ROS 2 into prefix (a fresh folder); raises with the log's tail."""
    work = prefix.with_name(prefix.name + ".work")
    shutil.rmtree(prefix, ignore_errors=True)
    shutil.rmtree(work, ignore_errors=True)
    jobs = str(os.cpu_count() or 2)
    log(f"building ROS 2 Jazzy from {VENDOR.name}/ into {prefix} ({toolchain_versions()}, {jobs} jobs; "
        "about 5 CPU-minutes and a 62 MB download from PyPI, once per source/toolchain change)")
    started = time.monotonic()
    output = prefix.with_name(prefix.name + ".log")
    env = {**os.environ, "PREFIX": str(prefix), "WORK_DIR": str(work), "JOBS": jobs}
    with output.open("w") as sink:
        result = subprocess.run(["bash", str(VENDOR / "build.sh")], stdout=sink, stderr=subprocess.STDOUT,
                                env=env)
    minutes = (time.monotonic() - started) / 60
    if result.returncode != 0 or not is_usable(prefix):
        lines = output.read_text(errors="replace").splitlines()
        detail = "\n".join(lines[-LOG_TAIL_LINES:])
        raise Ros2BuildFailed(f"building ROS 2 Jazzy failed after {minutes:.1f} min (log {output}):\n{detail}")
    for line in output.read_text().splitlines():
        if line.startswith("== "):
            log("  " + line.strip())
    shutil.rmtree(work, ignore_errors=True)
    complete_stamp(prefix).write_text(f"{toolchain_versions()}\n")
    log(f"built ROS 2 Jazzy in {minutes:.1f} min")


def ensure() -> Installation:
    """The prefix to test against, building it into the cache when there is none."""
    started = time.monotonic()
    found = find()
    if found is not None:
        log(f"ROS 2 Jazzy: {found.prefix} ({found.origin})")
        return found
    if not VENDOR.is_dir():
        raise Ros2Unavailable("no ROS 2 Jazzy prefix and no ../shared/vendor/ros2 to build one from")
    prefix = cached_prefix()
    prefix.parent.mkdir(parents=True, exist_ok=True)
    with open(prefix.with_name(prefix.name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # a second run waits for the first one's build
        if complete_stamp(prefix).is_file() and is_usable(prefix):
            log(f"ROS 2 Jazzy: {prefix} (built by a concurrent run, waited {time.monotonic() - started:.0f} s)")
            return Installation(prefix, "cache")
        marker = failure_marker(prefix)
        marker.unlink(missing_ok=True)
        try:
            build(prefix)
        except Ros2BuildFailed as failure:
            marker.write_text(str(failure))
            raise
    return Installation(prefix, "cache")


def main(argv: list[str]) -> int:
    if argv[1:] not in (["ensure"], ["find"]):
        print("usage: ros2.py ensure|find", file=sys.stderr)
        return 2
    try:
        found = ensure() if argv[1] == "ensure" else installation()
    except Ros2Unavailable as reason:
        log(f"ROS 2: {reason}")
        return 1
    except Ros2BuildFailed as failure:
        log(str(failure))
        return 1
    print(found.prefix)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))


def installation_for_tests() -> Installation:
    """:func:`installation` for a test fixture: with ../shared/vendor/ros2 beside the checkout (or
    ``ROS2_JAZZY_PREFIX`` set) a missing or failed build fails the test, with the build log's
    tail; without them the ROS 2 tests are skipped."""
    import pytest

    try:
        return installation()
    except Ros2BuildFailed as failure:
        pytest.fail(str(failure), pytrace=False)
    except Ros2Unavailable as reason:
        if VENDOR.is_dir() or os.environ.get("ROS2_JAZZY_PREFIX"):
            pytest.fail(str(reason), pytrace=False)
        pytest.skip(str(reason))

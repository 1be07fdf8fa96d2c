"""Building and launching the ROS 1 target's packages: a catkin workspace around gen's output,
one roscore on a free port for a module's launches, the nodes' start barrier cleared between
them."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from tests.support import build_cache

PYTHON = "/usr/bin/python3"  # the system python, which has catkin_pkg

needs_catkin = pytest.mark.skipif(
    shutil.which("catkin_make") is None or not Path("/usr/include/ros/ros.h").is_file()
    or not Path("/usr/share/std_msgs").is_dir() or not Path("/usr/share/message_generation").is_dir(),
    reason="the ROS 1 Debian packages are missing (./dev installs catkin libroscpp-dev ros-message-generation "
           "libstd-msgs-dev ros-std-msgs)")
needs_roslaunch = pytest.mark.skipif(
    shutil.which("roslaunch") is None or shutil.which("roscore") is None,
    reason="roslaunch and roscore are missing (./dev installs python3-roslaunch rosout python3-rostopic rosbash)")


def run(*command: str | Path, cwd: Path | None = None, timeout: int = 120) -> str:
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=timeout, cwd=cwd)
    assert result.returncode == 0, f"{command[0]} failed:\n{result.stdout[-4000:]}\n{result.stderr[-4000:]}"
    return result.stdout


def generate(model: Path, user: Path, ws: Path, *options: str) -> str:
    """A catkin workspace ``ws`` whose src/ is gen's output for ``model`` (gen's ``options``
    added), its user code ``user`` copied into src/user/ first; gen's output."""
    src = ws / "src"
    shutil.copytree(user, src / "user")
    return run(sys.executable, "-m", "earl_m2t", "gen", model, "--target", "ros", "-o", src, *options)


def catkin_make(ws: Path, *flags: str) -> Path:
    """The workspace ``ws`` (its src/) built with catkin_make, once per content
    (tests/support/build_cache.py): a workspace folder holding src/, build/ and devel/."""
    command = ["catkin_make", f"-DPYTHON_EXECUTABLE={PYTHON}", "-j", str(os.cpu_count() or 2), *flags]

    def build(folder: Path) -> None:
        run(command[0], "-C", folder, *command[1:], timeout=900)

    return build_cache.built("catkin", ws / "src", build, command)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def stop(process: subprocess.Popen[bytes]) -> None:
    """SIGINT (roslaunch then stops its nodes), then SIGKILL to the process group."""
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGINT)
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            pass
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    process.wait(timeout=10)


def clear_start_barrier(master: xmlrpc.client.ServerProxy) -> None:
    """Delete the previous run's /earl_ready parameters (the nodes' start barrier), waiting for
    the master to answer (the first time roscore may still be starting)."""
    deadline = time.monotonic() + 30
    while True:
        try:
            master.deleteParam("/test", "/earl_ready")
            return
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.1)


def environment(ws: Path, home: Path, port: int) -> dict[str, str]:
    """The environment of roscore and roslaunch for the workspace ``ws`` (outside any venv)."""
    env = dict(os.environ)
    env.update(ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1", ROS_HOME=str(home / "home"),
               ROS_PACKAGE_PATH=f"{ws / 'src'}:/usr/share", ROS_LOG_DIR=str(home / "log"))
    env["CMAKE_PREFIX_PATH"] = f"{ws / 'devel'}:/usr"
    env["PYTHONPATH"] = str(ws / "devel" / "lib" / "python3" / "dist-packages")
    env.pop("VIRTUAL_ENV", None)
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep) if ".venv" not in p)
    return env


@contextmanager
def roscore(home: Path) -> Iterator[tuple[int, xmlrpc.client.ServerProxy]]:
    """One roscore on a free port: (its port, its master)."""
    port = free_port()
    core = subprocess.Popen(["roscore", "-p", str(port)], env=environment(home, home, port),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        yield port, xmlrpc.client.ServerProxy(f"http://127.0.0.1:{port}")
    finally:
        stop(core)


def forget_nodes(master: xmlrpc.client.ServerProxy, keep: str = "/rosout") -> None:
    """Unregisters every node but ``keep`` from the master. A launch stopped with SIGKILL leaves
    its nodes registered; when a node of the next launch registers under the same name, the
    master tells the old node's address to shut down, and whichever new process took over that
    port dies ("new node registered with same name")."""
    caller = "/earl_test"
    _, _, (publishers, subscribers, services) = master.getSystemState(caller)
    addresses: dict[str, str] = {}

    def address(node: str) -> str | None:
        if node not in addresses:
            code, _, uri = master.lookupNode(caller, node)
            addresses[node] = uri if code == 1 else ""
        return addresses[node] or None

    for topic, nodes in publishers:
        for node in nodes:
            if node != keep and (uri := address(node)):
                master.unregisterPublisher(node, topic, uri)
    for topic, nodes in subscribers:
        for node in nodes:
            if node != keep and (uri := address(node)):
                master.unregisterSubscriber(node, topic, uri)
    for service, nodes in services:
        for node in nodes:
            if node != keep:
                code, _, service_uri = master.lookupService(caller, service)
                if code == 1:
                    master.unregisterService(node, service, service_uri)

"""The known-bad variants of the loaded campaigns (tests/support/campaigns.toml) build, each with
the same function its campaign's test builds it with, so the same content: among the tests that
run in parallel, while the loaded tests that launch them run one at a time afterwards and find
each build done (tests/support/build_cache.py). Each build is checked for what its launch needs."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests import (
    test_gen_orocos,
    test_gen_ros,
    test_gen_ros2,
    test_orocos_switch_runs,
    test_ros2_hosts,
    test_ros2_switch_runs,
    test_ros_switch_runs,
)
from tests.support import orocos, ros2
from tests.support.ros_launch import needs_catkin


@pytest.fixture(scope="module")
def jazzy() -> ros2.Installation:
    return ros2.installation_for_tests()


@pytest.fixture(scope="module")
def rtt() -> orocos.Installation:
    try:
        return orocos.installation()
    except (orocos.OrocosBuildFailed, orocos.OrocosUnavailable) as reason:
        pytest.fail(str(reason), pytrace=False)


def cs_nodes(install: Path) -> list[str]:
    return sorted(p.relative_to(install).as_posix() for p in install.glob("*/lib/*/cs_node"))


def test_the_ros2_latest_value_variant_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_gen_ros2.latest_value_built(jazzy, tmp_path)
    assert "pick_and_place_manip_a/lib/pick_and_place_manip_a/cs_node" in cs_nodes(built / "install")
    # the variant is what it says: manip/a.cs keeps the latest command only
    component = (built / "src" / "pick_and_place_manip_a" / "src" / "cs_component.cpp").read_text()
    assert '"~/manipulator_command_ib", rclcpp::QoS(rclcpp::KeepLast(1))' in component


def test_the_ros2_latest_value_variant_across_hosts_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_hosts.latest_value_built(jazzy, tmp_path)
    share = built / "install" / test_ros2_hosts.BRINGUP / "share" / test_ros2_hosts.BRINGUP / "launch"
    assert sorted(p.name for p in share.glob("*.launch.py")) == ["arm.launch.py", "hand.launch.py", "system.launch.py"]


def test_the_ros2_drain_skipping_variant_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_switch_runs.undrained_built(jazzy, tmp_path / "ws")
    assert cs_nodes(built / "install")
    assert "-DEARL_SWITCH_DRAIN=0" in (built / "build" / "two_arm_task_a" / "CMakeCache.txt").read_text()


@needs_catkin
def test_the_ros_latest_value_variant_builds(tmp_path: Path) -> None:
    built = test_gen_ros.latest_value_built(tmp_path)
    assert (built / "devel" / "lib" / "pick_and_place_manip_a" / "cs_node").is_file()


@needs_catkin
def test_the_ros_drain_skipping_variant_builds(tmp_path: Path) -> None:
    built = test_ros_switch_runs.undrained_built(tmp_path / "ws")
    assert "-DEARL_SWITCH_DRAIN=0" in (built / "build" / "CMakeCache.txt").read_text()


def test_the_orocos_latest_value_variant_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    out, installed = test_gen_orocos.latest_value_installed(rtt, tmp_path)
    assert (out / "deploy" / "manip_a_cs.ops").is_file() and any(installed.rglob("lib*-gnulinux.so"))


def test_the_orocos_drain_skipping_variant_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    out = test_orocos_switch_runs.generate(test_orocos_switch_runs.TWO_ARM, test_orocos_switch_runs.TWO_ARM.parent
                                           / "user", tmp_path / "two_arm")
    installed = test_orocos_switch_runs.install(out, rtt, "-DEARL_SWITCH_DRAIN=0")
    assert any(installed.rglob("lib*-gnulinux.so"))

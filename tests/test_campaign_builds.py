"""Every workspace the loaded campaigns (tests/support/campaigns.toml) launch builds among the
tests that run in parallel: the campaigns' own (pick_and_place, two_arm and harmoniser for ROS 1,
ROS 2 and Orocos), their known-bad variants, and the forced-switch and restarted-agent variants
the ROS 2, ROS 1 and Orocos modules launch once. Each build uses the same function its test builds
it with, so the same content (tests/support/build_cache.py): the loaded tests, which run one at a
time afterwards, and the module that launches it (the ROS 2 modules share one worker) find it
built. Each build is its own xdist group, so the two workers share them out, and each is checked
for what its launch needs.
"""

from __future__ import annotations

import re
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


def assert_every_package_installed(built: Path) -> None:
    """Every package gen wrote into src/ (but the user code) installed by colcon."""
    packages = sorted(p.parent.name for p in (built / "src").glob("*/package.xml"))
    assert packages and sorted(p.name for p in (built / "install").iterdir() if (p / "share").is_dir()) == packages


def catkin_nodes(built: Path) -> list[str]:
    return sorted(p.relative_to(built / "devel" / "lib").as_posix() for p in (built / "devel" / "lib").glob("*/*_node"))


def orocos_libraries(prefix: Path) -> list[str]:
    return sorted(p.name for p in prefix.rglob("lib*-gnulinux.so"))


def guide_reactivation(source: Path) -> str:
    """How the generated system restarts guide/a after a switch: 'resume' or 'restart'."""
    header = next(source.rglob("Harmoniser/system.hpp")).read_text()
    found = re.search(r'slot_guide_a\{"guide/a", earl::Reactivation::(\w+)\}', header)
    assert found, "no slot for guide/a in the generated system"
    return found.group(1)


@pytest.mark.xdist_group("build: ros2 latest-value")
def test_the_ros2_latest_value_variant_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_gen_ros2.latest_value_built(jazzy, tmp_path)
    assert "pick_and_place_manip_a/lib/pick_and_place_manip_a/cs_node" in cs_nodes(built / "install")
    # the variant is what it says: manip/a.cs keeps the latest command only
    component = (built / "src" / "pick_and_place_manip_a" / "src" / "cs_component.cpp").read_text()
    assert '"~/manipulator_command_ib", rclcpp::QoS(rclcpp::KeepLast(1))' in component


@pytest.mark.xdist_group("build: ros2 latest-value across hosts")
def test_the_ros2_latest_value_variant_across_hosts_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_hosts.latest_value_built(jazzy, tmp_path)
    share = built / "install" / test_ros2_hosts.BRINGUP / "share" / test_ros2_hosts.BRINGUP / "launch"
    assert sorted(p.name for p in share.glob("*.launch.py")) == ["arm.launch.py", "hand.launch.py", "system.launch.py"]


@pytest.mark.xdist_group("build: ros2 drain-skipping")
def test_the_ros2_drain_skipping_variant_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_switch_runs.undrained_built(jazzy, tmp_path / "ws")
    assert cs_nodes(built / "install")
    assert "-DEARL_SWITCH_DRAIN=0" in (built / "build" / "two_arm_task_a" / "CMakeCache.txt").read_text()


@needs_catkin
@pytest.mark.xdist_group("build: ros latest-value")
def test_the_ros_latest_value_variant_builds(tmp_path: Path) -> None:
    built = test_gen_ros.latest_value_built(tmp_path)
    assert (built / "devel" / "lib" / "pick_and_place_manip_a" / "cs_node").is_file()


@needs_catkin
@pytest.mark.xdist_group("build: ros drain-skipping")
def test_the_ros_drain_skipping_variant_builds(tmp_path: Path) -> None:
    built = test_ros_switch_runs.undrained_built(tmp_path / "ws")
    assert "-DEARL_SWITCH_DRAIN=0" in (built / "build" / "CMakeCache.txt").read_text()


@pytest.mark.xdist_group("build: orocos latest-value")
def test_the_orocos_latest_value_variant_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    out, installed = test_gen_orocos.latest_value_installed(rtt, tmp_path)
    assert (out / "deploy" / "manip_a_cs.ops").is_file() and any(installed.rglob("lib*-gnulinux.so"))


@pytest.mark.xdist_group("build: orocos drain-skipping")
def test_the_orocos_drain_skipping_variant_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    out = test_orocos_switch_runs.generate(test_orocos_switch_runs.TWO_ARM, test_orocos_switch_runs.TWO_ARM.parent
                                           / "user", tmp_path / "two_arm")
    installed = test_orocos_switch_runs.install(out, rtt, "-DEARL_SWITCH_DRAIN=0")
    assert any(installed.rglob("lib*-gnulinux.so"))


# ------------------------------------------------- the campaigns' own workspaces and variants


@pytest.mark.xdist_group("build: ros2 pick_and_place")
def test_the_ros2_pick_and_place_workspace_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_gen_ros2.sample_built(jazzy, tmp_path / "ws")
    assert_every_package_installed(built)
    assert len(cs_nodes(built / "install")) == 3


@pytest.mark.xdist_group("build: ros2 two_arm")
def test_the_ros2_two_arm_workspace_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_switch_runs.two_arm_built(jazzy, tmp_path / "ws")
    assert_every_package_installed(built)


@pytest.mark.xdist_group("build: ros2 two_arm forced")
def test_the_ros2_forced_two_arm_workspace_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_switch_runs.forced_built(jazzy, tmp_path)
    assert_every_package_installed(built)


@pytest.mark.xdist_group("build: ros2 harmoniser")
def test_the_ros2_harmoniser_workspace_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_switch_runs.harmoniser_built(jazzy, tmp_path / "ws")
    assert_every_package_installed(built)
    assert guide_reactivation(built / "src") == "resume"


@pytest.mark.xdist_group("build: ros2 harmoniser restarted")
def test_the_ros2_restarted_harmoniser_workspace_builds(jazzy: ros2.Installation, tmp_path: Path) -> None:
    built = test_ros2_switch_runs.restarted_built(jazzy, tmp_path)
    assert_every_package_installed(built)
    assert guide_reactivation(built / "src") == "restart"


@needs_catkin
@pytest.mark.xdist_group("build: ros two_arm")
def test_the_ros_two_arm_workspace_builds(tmp_path: Path) -> None:
    built = test_ros_switch_runs.workspace(tmp_path / "ws", test_ros_switch_runs.TWO_ARM)
    assert catkin_nodes(built)


@needs_catkin
@pytest.mark.xdist_group("build: ros two_arm forced")
def test_the_ros_forced_two_arm_workspace_builds(tmp_path: Path) -> None:
    assert catkin_nodes(test_ros_switch_runs.forced_built(tmp_path))


@needs_catkin
@pytest.mark.xdist_group("build: ros harmoniser")
def test_the_ros_harmoniser_workspace_builds(tmp_path: Path) -> None:
    built = test_ros_switch_runs.workspace(tmp_path / "ws", test_ros_switch_runs.HARMONISER)
    assert catkin_nodes(built)
    assert guide_reactivation(built / "src") == "resume"


@needs_catkin
@pytest.mark.xdist_group("build: ros harmoniser restarted")
def test_the_ros_restarted_harmoniser_workspace_builds(tmp_path: Path) -> None:
    built = test_ros_switch_runs.restarted_built(tmp_path)
    assert catkin_nodes(built)
    assert guide_reactivation(built / "src") == "restart"


@pytest.mark.xdist_group("build: orocos two_arm")
def test_the_orocos_two_arm_project_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    _, prefix = test_orocos_switch_runs.installed(test_orocos_switch_runs.TWO_ARM, rtt, tmp_path / "out")
    assert orocos_libraries(prefix)


@pytest.mark.xdist_group("build: orocos two_arm forced")
def test_the_orocos_forced_two_arm_project_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    _, prefix = test_orocos_switch_runs.forced_installed(rtt, tmp_path)
    assert orocos_libraries(prefix)


@pytest.mark.xdist_group("build: orocos harmoniser")
def test_the_orocos_harmoniser_project_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    out, prefix = test_orocos_switch_runs.installed(test_orocos_switch_runs.HARMONISER, rtt, tmp_path / "out")
    assert orocos_libraries(prefix)
    assert guide_reactivation(out) == "resume"


@pytest.mark.xdist_group("build: orocos harmoniser restarted")
def test_the_orocos_restarted_harmoniser_project_builds(rtt: orocos.Installation, tmp_path: Path) -> None:
    out, prefix = test_orocos_switch_runs.restarted_installed(rtt, tmp_path)
    assert orocos_libraries(prefix)
    assert guide_reactivation(out) == "restart"

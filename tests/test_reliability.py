"""The tags reliability of «InputBuffer» and «OutputBuffer»: lifted from Papyrus XMI and SysML v2,
shown, written back by convert (the converted model does not differ from its source), and
turned into the reliability of the ROS 2 publishers and subscriptions.

The encoder stream of the sample (Motor's encoder/ob into MotorController's encoder/ib, and the
finger's) is the case best effort is for: a sensor value that the next one soon replaces."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

from earl_m2t.api import load
from tests.rules.test_rule_triggers import Sample

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place"
ENCODERS = ("manip/a.motor1/re.encoder/ob", "manip/a.motorController1/ve.encoder/ib",
            "grip/a.fingerMotor/re.encoder/ob", "grip/a.fingerController/ve.encoder/ib")
IB = "            port 'encoder/ib' : InputBuffer { attribute :>> msg : DataTypes::EncoderReading; }\n"
OB = "            port 'encoder/ob' : OutputBuffer { attribute :>> msg : DataTypes::EncoderReading; }\n"


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], capture_output=True, text=True, timeout=300)


def papyrus_model(tmp_path: Path, tagged: tuple[tuple[str, str, str], ...]) -> Path:
    """The Papyrus sample with the tag reliability = best_effort on (stereotype, block, port)."""
    sample = Sample((SAMPLE / "pick_and_place.uml").read_bytes())
    for concept, block, port in tagged:
        sample.application(concept, sample.attribute(block, port)).set("reliability", "best_effort")
    path = tmp_path / "pick_and_place.uml"
    path.write_bytes(sample.to_bytes())
    shutil.copy(SAMPLE / "EARL.profile.uml", tmp_path / "EARL.profile.uml")
    return path


def sysml_model(tmp_path: Path, inputs: bool = True) -> Path:
    """The SysML v2 sample whose encoder/ob ports (and encoder/ib ports, with ``inputs``) are best_effort."""
    text = (SAMPLE / "pick_and_place.sysml").read_text(encoding="utf-8")
    assert text.count(IB) == 2 and text.count(OB) >= 1
    text = text.replace(OB, OB.replace("; }", "; @OutputBuffer { reliability = Reliability::best_effort; } }"))
    if inputs:
        text = text.replace(IB, IB.replace("; }", "; @InputBuffer { reliability = Reliability::best_effort; } }"))
    path = tmp_path / "pick_and_place.sysml"
    path.write_text(text, encoding="utf-8")
    return path


def reliabilities(path: Path) -> dict[str, str]:
    """Every buffer's reliability other than reliable, by path."""
    model = load(path).model
    return {b.path: b.reliability for sub in model.subsystems for b in sub.inputs + sub.outputs
            if b.reliability != "reliable"}


def assert_round_trip(source: Path, tmp_path: Path) -> None:
    converted = tmp_path / "converted.sysml"
    result = earl("convert", str(source), "--to", "sysml", "-o", str(converted))
    assert result.returncode == 0, result.stderr
    assert reliabilities(converted) == reliabilities(source)
    diff = earl("diff", str(source), str(converted))
    assert (diff.returncode, diff.stdout) == (0, ""), diff.stdout + diff.stderr


def test_papyrus_tags_are_lifted_shown_and_converted_back(tmp_path: Path) -> None:
    source = papyrus_model(tmp_path, (("OutputBuffer", "Motor", "encoder/ob"),
                                      ("InputBuffer", "MotorController", "encoder/ib")))
    found = reliabilities(source)
    assert set(found.values()) == {"best_effort"}
    assert set(ENCODERS[:2]) <= set(found) and not set(ENCODERS[2:]) & set(found)
    shown = earl("show", str(source))
    assert shown.returncode == 0, shown.stderr
    assert re.findall(r"^ +(?:ib|ob) encoder/\w+ : \S+(.*)$", shown.stdout, re.MULTILINE) == [
        "  best_effort", "  best_effort", "", ""]
    assert_round_trip(source, tmp_path)


def test_sysml_tags_are_lifted_and_converted_back(tmp_path: Path) -> None:
    source = sysml_model(tmp_path)
    assert set(ENCODERS) <= set(reliabilities(source))
    assert_round_trip(source, tmp_path)


def component(out: Path, package: str, node: str) -> str:
    return (out / f"pick_and_place_{package}" / "src" / f"{node}_component.cpp").read_text(encoding="utf-8")


def test_ros2_publishes_and_subscribes_best_effort_where_the_tags_say(tmp_path: Path) -> None:
    source = sysml_model(tmp_path)
    result = earl("gen", str(source), "--target", "ros2", "-o", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    motor = component(tmp_path / "out", "manip_a", "motor_k_re")
    assert re.search(r'"~/encoder_ob", rclcpp::QoS\(rclcpp::KeepLast\(1\)\)\.best_effort\(\)', motor)
    assert re.search(r'"~/desired_current_ib", rclcpp::QoS\(rclcpp::KeepLast\(1\)\)\.reliable\(\)', motor)
    controller = component(tmp_path / "out", "manip_a", "motor_controller_k_ve")
    assert re.search(r'"~/encoder_ib", rclcpp::QoS\(rclcpp::KeepLast\(1\)\)\.best_effort\(\)\.transient_local\(\)',
                     controller)
    assert controller.count(".best_effort()") == 1


def test_a_reliable_output_serves_a_best_effort_input_with_a_reliable_publisher(tmp_path: Path) -> None:
    source = papyrus_model(tmp_path, (("InputBuffer", "FingerController", "encoder/ib"),))
    result = earl("gen", str(source), "--target", "ros2", "-o", str(tmp_path / "out"))
    assert result.returncode == 0, result.stderr
    motor = component(tmp_path / "out", "grip_a", "finger_motor_re")
    assert ".best_effort()" not in motor and re.search(r'"~/encoder_ob", rclcpp::QoS\([^;]*\.reliable\(\)', motor)
    assert '"~/encoder_ib", rclcpp::QoS(rclcpp::KeepLast(1)).best_effort()' in component(
        tmp_path / "out", "grip_a", "finger_controller_ve")


def test_gen_refuses_a_best_effort_output_into_a_reliable_input(tmp_path: Path) -> None:
    result = earl("gen", str(sysml_model(tmp_path, inputs=False)), "--target", "ros2", "-o", str(tmp_path / "out"))
    assert result.returncode != 0
    assert "C010" in result.stdout + result.stderr and "nothing generated" in result.stderr

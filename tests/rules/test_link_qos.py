"""Rule C010 (link-qos-incompatible) stays quiet on the pairs ROS 2 serves and reports a queue fed
best effort; its triggers are rows of test_rule_triggers.py. Mutations of the sample's tag
reliability, checked as the command line checks."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t import check
from tests.rules.test_rule_triggers import Sample

FINGER_ENCODER = (("OutputBuffer", "FingerMotor", "encoder/ob"), ("InputBuffer", "FingerController", "encoder/ib"))


def _findings(sample_bytes: bytes, tmp_path: Path, tagged: tuple[tuple[str, str, str], ...]) -> list[str]:
    sample = Sample(sample_bytes)
    for concept, block, port in tagged:
        sample.application(concept, sample.attribute(block, port)).set("reliability", "best_effort")
    path = tmp_path / "variant.uml"
    path.write_bytes(sample.to_bytes())
    return [f"{d.code} {d.message}" for d in check(path)]


@pytest.mark.parametrize("tagged", [FINGER_ENCODER[1:], FINGER_ENCODER], ids=["reader-only", "both"])
def test_a_best_effort_reader_of_a_latest_value_is_served(sample_bytes: bytes, tmp_path: Path,
                                                          tagged: tuple[tuple[str, str, str], ...]) -> None:
    assert _findings(sample_bytes, tmp_path, tagged) == []


def test_a_queue_fed_by_a_best_effort_output_is_reported_at_its_link(sample_bytes: bytes, tmp_path: Path) -> None:
    found = _findings(sample_bytes, tmp_path, (("OutputBuffer", "TaskControl", "manipulatorCommand/ob"),))
    assert found == ["C010 link task/a,manip/a (task/a.cs.manipulatorCommand/ob → manip/a.cs.manipulatorCommand/ib): "
                     "the Input Buffer receives a queue, which loses no value silently, but the Output Buffer is "
                     "best_effort; make it reliable (tag reliability)"]


def test_a_queued_best_effort_input_that_no_link_feeds_is_reported_at_the_buffer(sample_bytes: bytes,
                                                                                  tmp_path: Path) -> None:
    sample = Sample(sample_bytes)
    sample.remove(sample.connector("PickAndPlaceSystem", "task/a,manip/a"))
    sample.application("InputBuffer", sample.attribute("ManipulatorControl", "manipulatorCommand/ib")).set(
        "reliability", "best_effort")
    path = tmp_path / "variant.uml"
    path.write_bytes(sample.to_bytes())
    found = [d for d in check(path) if d.code == "C010"]
    assert [(d.message, d.location.xmi_id) for d in found] == [
        ("Input Buffer manip/a.cs.manipulatorCommand/ib receives a queue, which loses no value silently, but is "
         "best_effort; make it reliable (tag reliability)",
         sample.id(sample.attribute("ManipulatorControl", "manipulatorCommand/ib")))]

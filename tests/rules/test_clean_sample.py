"""The reference sample triggers no rule, and neither does its suffix-only twin.

``scripts/make_sample.py`` writes the sample with an EARL stereotype on every EARL element;
``build(stereotypes=False)`` writes the same model recognised by name suffixes alone
(modelling guide, section 1, route 3). Both must check clean, and both must lift to the
same EARL model: the ``show --format json`` structure is equal once the recognition route,
lines and xmi:ids are left out. Tagged values are the one documented difference: only the
stereotype route can carry them, so the twin has no declared agent types and every
transition has the default priority 0.
"""

from __future__ import annotations

from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from earl_m2t import CheckOptions, check, load
from earl_m2t.export import model_to_dict

# Keys of the JSON export that depend on how an element was recognised or where it is.
UNCOMPARED = frozenset({"recognised_by", "line", "xmi_id"})
# Tagged values of the EARL stereotypes (modelling guide, section 1: only route 1 carries them),
# the activation among them: buffer groups are «BufferGroup» constraints.
TAGGED = frozenset({"declared_type", "priority", "receive", "queue_size", "activation", "buffer_groups"})


def _normalised(data: Any, drop: frozenset[str]) -> Any:
    if isinstance(data, dict):
        return {key: _normalised(value, drop) for key, value in data.items() if key not in drop}
    if isinstance(data, list):
        return [_normalised(value, drop) for value in data]
    return data


def _values(data: Any, key: str) -> list[Any]:
    """Every value of ``key`` anywhere in the exported structure."""
    if isinstance(data, dict):
        found = [data[key]] if key in data else []
        return found + [v for value in data.values() for v in _values(value, key)]
    if isinstance(data, list):
        return [v for value in data for v in _values(value, key)]
    return []


def _exported(path: Path) -> dict[str, Any]:
    data = model_to_dict(load(path).model)
    data["file"] = Path(data["file"]).name
    return data


@pytest.fixture
def suffix_only(make_sample: ModuleType, sample_path: Path, tmp_path: Path) -> Path:
    path = tmp_path / sample_path.name
    path.write_bytes(make_sample.build(stereotypes=False))
    return path


def test_sample_checks_clean(sample_path: Path) -> None:
    findings = check(sample_path)
    assert findings == [], "\n".join(f"{d.code} {d.location}: {d.message}" for d in findings)


def test_sample_checks_clean_with_info_findings_enabled(sample_path: Path) -> None:
    every_rule = CheckOptions(select=None, ignore=frozenset())
    assert check(sample_path, every_rule) == []


def test_suffix_only_variant_carries_no_earl_stereotype(suffix_only: Path) -> None:
    text = suffix_only.read_text(encoding="utf-8")
    assert "EARL:" not in text
    assert "xmlns:EARL" not in text


def test_suffix_only_variant_checks_clean(suffix_only: Path) -> None:
    """Clean but for the tags it cannot carry: without the priorities the self-transitions of
    jointMove and operationalMove tie with the transitions back to idle, and every transition
    leaving on a command ties with the one into emergencyStop on inError() (B006; model order
    picks the first, where the priorities pick emergencyStop in the sample); without the receive
    mode task/a's one-shot setpoint goes to a latest-value input (C009)."""
    findings = check(suffix_only)
    described = "\n".join(f"{d.code} {d.location}: {d.message}" for d in findings)
    assert [(d.code, d.element) for d in findings] == [
        ("C009", "manip/a.cs.manipulatorCommand/ib"),
        ("B006", "manip/a.cs.fsm.idle,jointMove/t"),
        ("B006", "manip/a.cs.fsm.jointMove,jointMove/t"),
        ("B006", "manip/a.cs.fsm.jointMove,jointMove/t"),
        ("B006", "manip/a.cs.fsm.idle,operationalMove/t"),
        ("B006", "manip/a.cs.fsm.operationalMove,operationalMove/t"),
        ("B006", "manip/a.cs.fsm.operationalMove,operationalMove/t"),
        ("B006", "manip/a.cs.fsm.jointMove,idle/t"),
        ("B006", "manip/a.cs.fsm.operationalMove,idle/t"),
    ], described
    assert check(suffix_only, CheckOptions(ignore=frozenset({"B006", "C009"}))) == [], described


def test_suffix_only_variant_is_recognised_by_suffix(sample_path: Path, suffix_only: Path) -> None:
    assert set(_values(_exported(sample_path), "recognised_by")) == {"stereotype"}
    # the System block has no suffix: it is the top-level block whose parts are robots and agents
    assert set(_values(_exported(suffix_only), "recognised_by")) == {"suffix", "structure"}


def test_suffix_only_variant_lifts_to_the_same_model(sample_path: Path, suffix_only: Path) -> None:
    drop = UNCOMPARED | TAGGED
    assert _normalised(_exported(suffix_only), drop) == _normalised(_exported(sample_path), drop)


def test_suffix_only_variant_has_only_default_tagged_values(sample_path: Path, suffix_only: Path) -> None:
    sample, twin = _exported(sample_path), _exported(suffix_only)
    assert set(_values(sample, "declared_type")) == {"CT", "CET"}
    assert set(_values(twin, "declared_type")) == {None}
    assert set(_values(sample, "priority")) == {0, 1, 2}
    assert set(_values(twin, "priority")) == {0}
    assert set(_values(sample, "receive")) == {"latest", "queue"}
    assert set(_values(twin, "receive")) == {"latest"}
    assert _values(twin, "buffer_groups") and not any(_values(twin, "buffer_groups"))
    # everything else the tags sit next to is the same
    assert _normalised(twin, UNCOMPARED | TAGGED) == _normalised(sample, UNCOMPARED | TAGGED)
    assert len(_values(twin, "priority")) == len(_values(sample, "priority"))

"""The reference sample, written by Papyrus, Cameo and Enterprise Architect, lifts to one EARL model.

The three files of ``samples/pick_and_place/`` carry the same model (``scripts/make_sample.py``).
Read by their dialects and lifted, they must give the same ``show --format json`` document,
apart from what names the file (``file``, ``dialect``) and where things are in it (``line``,
``xmi_id``), and each must check clean.

The Enterprise Architect file cannot say two things the Papyrus file says, so its comparison
leaves them out (and the strict comparison is expected to fail until the sample says them):

- order: EA keeps the members of a package, a block and a region sorted by name, so agents,
  subsystems, buffers, states, transitions, functions, predicates and links come in name order,
  not in modelling order;
- languages: EA's "XMI 2.1" export writes an opaque behaviour's text as a ``body=`` attribute
  without a language, so partial transition functions (``C++`` in the Papyrus sample) and
  primitive predicates (``EARL``) have none.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from earl_m2t.api import check, load
from earl_m2t.export import model_to_dict

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples" / "pick_and_place"
FILES = {
    "papyrus": SAMPLES / "pick_and_place.uml",
    "cameo": SAMPLES / "pick_and_place.cameo.xmi",
    "ea": SAMPLES / "pick_and_place.ea.xml",
}
DIALECTS = {"papyrus": "papyrus", "cameo": "cameo", "ea": "enterprise-architect"}
WHERE = frozenset({"file", "dialect", "line", "xmi_id"})
NAME_LISTS = frozenset({"agents"})  # lists of names kept in model order (a robot's agents)
EA_WITHOUT_LANGUAGE = ("functions", "predicates")


def _present(name: str) -> Path:
    path = FILES[name]
    if not path.is_file():
        pytest.skip(f"{path.name} is not in the checkout")
    return path


def without_location(value: Any) -> Any:
    """The document with every ``file``, ``dialect``, ``line`` and ``xmi_id`` key removed."""
    if isinstance(value, dict):
        return {key: without_location(item) for key, item in value.items() if key not in WHERE}
    if isinstance(value, list):
        return [without_location(item) for item in value]
    return value


def lifted(name: str) -> dict[str, Any]:
    return without_location(model_to_dict(load(_present(name)).model))


def in_name_order(value: Any) -> Any:
    """The document with lists of elements (and of agent names) sorted by path or name."""
    if isinstance(value, dict):
        return {
            key: sorted(item) if key in NAME_LISTS and all(isinstance(i, str) for i in item) else in_name_order(item)
            for key, item in value.items()
        }
    if isinstance(value, list):
        items = [in_name_order(item) for item in value]
        if items and all(isinstance(item, dict) for item in items):
            return sorted(items, key=lambda item: str(item.get("path") or item.get("name") or ""))
        return items
    return value


def without_behaviour_languages(value: Any, feature: str = "") -> Any:
    """The document without the ``language`` of partial transition functions and primitive predicates."""
    if isinstance(value, dict):
        return {
            key: without_behaviour_languages(item, key)
            for key, item in value.items()
            if not (key == "language" and feature in EA_WITHOUT_LANGUAGE)
        }
    if isinstance(value, list):
        return [without_behaviour_languages(item, feature) for item in value]
    return value


@pytest.fixture(scope="module")
def papyrus() -> dict[str, Any]:
    return lifted("papyrus")


def test_the_papyrus_sample_holds_the_whole_earl_model(papyrus: dict[str, Any]) -> None:
    assert papyrus["earl"] is True and papyrus["model"] == "PickAndPlace"
    (system,) = papyrus["systems"]
    assert [agent["name"] for agent in system["agents"]] == ["manip/a", "grip/a", "task/a"]
    assert len(system["links"]) == 4 and len(papyrus["datatypes"]) == 14


def test_the_cameo_sample_lifts_to_the_papyrus_model(papyrus: dict[str, Any]) -> None:
    assert lifted("cameo") == papyrus


@pytest.mark.xfail(strict=True, reason="the EA sample keeps members in name order and writes no behaviour languages")
def test_the_enterprise_architect_sample_lifts_to_the_papyrus_model(papyrus: dict[str, Any]) -> None:
    assert lifted("ea") == papyrus


def test_the_enterprise_architect_sample_differs_only_in_order_and_behaviour_languages(
    papyrus: dict[str, Any],
) -> None:
    ea = lifted("ea")
    assert ea != papyrus
    assert in_name_order(without_behaviour_languages(ea)) == in_name_order(without_behaviour_languages(papyrus))
    assert without_behaviour_languages(ea) != without_behaviour_languages(papyrus)  # the order differs
    assert in_name_order(ea) != in_name_order(papyrus)  # and so do the languages


@pytest.mark.parametrize("name", list(FILES))
def test_each_sample_is_read_in_its_own_dialect(name: str) -> None:
    assert load(_present(name)).model.dialect == DIALECTS[name]


@pytest.mark.parametrize("name", list(FILES))
def test_each_sample_checks_clean(name: str) -> None:
    assert [str(d) for d in check(_present(name))] == []

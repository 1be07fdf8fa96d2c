"""The samples, written by Papyrus, Cameo, Enterprise Architect and as SysML v2 text, lift to one EARL model.

The three XMI files of ``samples/pick_and_place/`` carry the same model (``scripts/make_sample.py``),
and so do those of ``samples/two_arm/`` (``scripts/make_two_arm.py``); each sample's ``.sysml``
says it by hand. Read by their dialects and lifted, a sample's files must give the same
``show --format json`` document, apart from what names the file (``file``, ``dialect``) and
where things are in it (``line``, ``xmi_id``), and each must check clean.

The Enterprise Architect file says two things differently, and the reader takes them from
where EA keeps them:

- order: EA exports a package's, a block's and a region's elements in Project Browser order;
  the sample's modeller keeps the browser in model order (free sort, tree positions 1, 2 …).
  Transitions and connectors, which the browser does not show, come after their source
  element; EA's number for each (``ea_localid``, handed out as they are created) gives their
  model order back;
- languages: EA writes an opaque behaviour's text as a ``body=`` attribute without a language;
  the language (``C++`` for the partial transition functions, ``EARL`` for the primitive
  predicates) is the element's Language, ``<code gentype="…"/>`` in its ``xmi:Extension`` record.
"""

from __future__ import annotations

from functools import cache
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
TWO_ARM = ROOT / "samples" / "two_arm"
# every sample, by name: its file in each dialect (Papyrus first, the one the others are compared with)
SAMPLE_FILES = {
    "pick_and_place": {**FILES, "sysml": SAMPLES / "pick_and_place.sysml"},
    "two_arm": {
        "papyrus": TWO_ARM / "two_arm.uml",
        "cameo": TWO_ARM / "two_arm.cameo.xmi",
        "ea": TWO_ARM / "two_arm.ea.xml",
        "sysml": TWO_ARM / "two_arm.sysml",
    },
}
DIALECTS = {"papyrus": "papyrus", "cameo": "cameo", "ea": "enterprise-architect", "sysml": "sysml-v2"}
WHERE = frozenset({"file", "dialect", "line", "xmi_id"})
EVERY = [(sample, name) for sample, files in SAMPLE_FILES.items() for name in files]
OTHERS = [(sample, name) for sample, name in EVERY if name != "papyrus"]


def _present(name: str, sample: str = "pick_and_place") -> Path:
    path = SAMPLE_FILES[sample][name]
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


def lifted(name: str, sample: str = "pick_and_place") -> dict[str, Any]:
    return without_location(model_to_dict(load(_present(name, sample)).model))


@cache
def _papyrus(sample: str) -> dict[str, Any]:
    return lifted("papyrus", sample)


@pytest.fixture(scope="module")
def papyrus() -> dict[str, Any]:
    return _papyrus("pick_and_place")


def test_the_papyrus_sample_holds_the_whole_earl_model(papyrus: dict[str, Any]) -> None:
    assert papyrus["earl"] is True and papyrus["model"] == "PickAndPlace"
    (system,) = papyrus["systems"]
    assert [agent["name"] for agent in system["agents"]] == ["manip/a", "grip/a", "task/a"]
    assert len(system["links"]) == 4 and len(papyrus["datatypes"]) == 14


def test_the_two_arm_papyrus_sample_holds_both_arms_and_the_four_links() -> None:
    two_arm = _papyrus("two_arm")
    assert two_arm["earl"] is True and two_arm["model"] == "TwoArm"
    (system,) = two_arm["systems"]
    assert [agent["name"] for agent in system["agents"]] == ["manipA/a", "manipB/a", "task/a"]
    assert [link["name"] for link in system["links"]] == [
        "task/a,manipA/a", "manipA/a,task/a", "task/a,manipB/a", "manipB/a,task/a"]


def test_the_two_arm_sample_says_how_its_structure_varies() -> None:
    """What every dialect must carry to be equal is there: the configurations, the optional
    arms, the coordinator's configurations and the arms' quiescent state."""
    (system,) = _papyrus("two_arm")["systems"]
    assert [(c["name"], c["agents"], c["links"], c["switch_timeout"]) for c in system["configurations"]] == [
        ("useA", ["manipA/a"], ["task/a,manipA/a", "manipA/a,task/a"], 0.05),
        ("useB", ["manipB/a"], ["task/a,manipB/a", "manipB/a,task/a"], 0.05),
    ]
    agents = {agent["name"]: agent for agent in system["agents"]}
    assert [name for name, agent in agents.items() if agent.get("optional")] == ["manipA/a", "manipB/a"]
    assert {agents[arm]["reactivation"] for arm in ("manipA/a", "manipB/a")} == {"restart"}

    def states(agent: str, key: str) -> dict[str, Any]:
        return {state["name"]: state.get(key) for state in agents[agent]["subsystems"][0]["fsm"]["states"]}

    assert states("task/a", "configuration") == {"withA": "useA", "withB": "useB", "finished": None}
    assert states("manipA/a", "quiescent") == states("manipB/a", "quiescent") == {"idle": True, "moving": None}
    guards = [t["condition"] for t in agents["manipA/a"]["subsystems"][0]["fsm"]["transitions"]]
    assert sum("leaving()" in guard for guard in guards) == 1


@pytest.mark.parametrize(("sample", "name"), OTHERS)
def test_each_sample_lifts_to_its_papyrus_model(sample: str, name: str) -> None:
    assert lifted(name, sample) == _papyrus(sample)


def test_the_behaviour_languages_and_the_orders_compared_are_those_of_the_paper_sample(
    papyrus: dict[str, Any],
) -> None:
    """What the EA file must get right to be equal is there to get right: languages, and orders
    that EA's grouping by source (transitions, links) or name sorting would change."""
    manip = papyrus["systems"][0]["agents"][0]["subsystems"][0]
    assert {pf["language"] for pf in manip["functions"]} == {"C++"}
    assert {pp["language"] for pp in manip["predicates"]} == {"EARL"}
    transitions = [t["name"] for t in manip["fsm"]["transitions"]]
    sources = [name.partition(",")[0] for name in transitions]
    assert sources != sorted(sources, key=sources.index) and transitions != sorted(transitions)
    links = [link["name"] for link in papyrus["systems"][0]["links"]]
    assert links == ["task/a,manip/a", "manip/a,task/a", "task/a,grip/a", "grip/a,task/a"]


@pytest.mark.parametrize(("sample", "name"), EVERY)
def test_each_sample_is_read_in_its_own_dialect(sample: str, name: str) -> None:
    assert load(_present(name, sample)).model.dialect == DIALECTS[name]


@pytest.mark.parametrize(("sample", "name"), EVERY)
def test_each_sample_checks_clean(sample: str, name: str) -> None:
    assert [str(d) for d in check(_present(name, sample))] == []

"""The samples, written by Papyrus, Cameo, Enterprise Architect and as SysML v2 text, lift to one EARL model.

The three XMI files of ``samples/pick_and_place/`` carry the same model (``scripts/make_sample.py``),
and so do those of ``samples/two_arm/`` (``scripts/make_two_arm.py``) and of
``samples/harmoniser/`` (``scripts/make_harmoniser.py``); each sample's ``.sysml`` says it by
hand. Read by their dialects and lifted, a sample's files must give the same
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


def dialect_files(sample: str) -> dict[str, Path]:
    """The files of ``samples/SAMPLE/`` in each dialect, named after the sample (Papyrus first,
    the one the others are compared with)."""
    folder = ROOT / "samples" / sample
    return {"papyrus": folder / f"{sample}.uml", "cameo": folder / f"{sample}.cameo.xmi",
            "ea": folder / f"{sample}.ea.xml", "sysml": folder / f"{sample}.sysml"}


# every sample, by name: its file in each dialect
SAMPLE_FILES = {sample: dialect_files(sample) for sample in ("pick_and_place", "two_arm", "harmoniser")}
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
        ("useA", ["manipA/a"], ["task/a,manipA/a", "manipA/a,task/a"], 0.1),
        ("useB", ["manipB/a"], ["task/a,manipB/a", "manipB/a,task/a"], 0.1),
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


def test_the_harmoniser_sample_brings_each_task_agent_in_and_resumes_it() -> None:
    """The harmoniser's variable structure: three configurations (one of them without a task
    agent), two optional task agents that resume, the coordinator tha/a.cs and each task
    agent's quiescent waiting state, left when leaving() is true."""
    harmoniser = _papyrus("harmoniser")
    assert harmoniser["earl"] is True and harmoniser["model"] == "Harmoniser"
    (system,) = harmoniser["systems"]
    assert [(c["name"], c["agents"], c["links"]) for c in system["configurations"]] == [
        ("none", [], []),
        ("guiding", ["guide/a"], ["guide/a,tiago/a", "tiago/a,guide/a"]),
        ("fallResponse", ["fallHelp/a"], ["fallHelp/a,tiago/a", "tiago/a,fallHelp/a"]),
    ]
    agents = {agent["name"]: agent for agent in system["agents"]}
    assert list(agents) == ["tiago/a", "tha/a", "guide/a", "fallHelp/a"]
    assert {name: (agent.get("optional", False), agent.get("reactivation")) for name, agent in agents.items()} == {
        "tiago/a": (False, None), "tha/a": (False, None),
        "guide/a": (True, "resume"), "fallHelp/a": (True, "resume")}
    assert [subsystem["name"] for subsystem in agents["tiago/a"]["subsystems"]] == [
        "cs", "base/ve", "base/re", "arm/ve", "arm/re", "lidar/vr", "lidar/rr"]

    def fsm(agent: str) -> dict[str, Any]:
        return agents[agent]["subsystems"][0]["fsm"]

    assert {s["name"]: s.get("configuration") for s in fsm("tha/a")["states"]} == {
        "idle": "none", "guiding": "guiding", "fallResponse": "fallResponse"}
    for task in ("guide/a", "fallHelp/a"):
        assert {s["name"]: s.get("quiescent") for s in fsm(task)["states"]}["waiting"] is True
        assert all("leaving()" in t["condition"] for t in fsm(task)["transitions"])


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

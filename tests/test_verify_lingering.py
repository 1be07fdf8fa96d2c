"""A link whose sender leaves and whose receiver stays lingers through a switch until its sender
has stopped (variability.lingers), in verify's Promela: the condition under which a variable
link delivers means exactly that, over every pair of configurations (the samples' and drawn
ones); what a leaving agent sends while it drains reaches the agent that stays, so V009 (a
leaving agent's send is dropped) holds on the samples. With the links closed at the decision,
as they were before, V009 finds the drop (the harmoniser's guide/a, leaving, still sends its
task command to tiago/a) and a task waiting for the status a leaving manipulator sent
deadlocks; a send to an agent leaving too is dropped under either."""

from __future__ import annotations

import json
import random
import re
from dataclasses import replace
from itertools import product
from pathlib import Path

import pytest
from test_sample_dialects_equal import SAMPLE_FILES
from test_verify_variability import PER_LINK, _variant

from earl_m2t.api import load
from earl_m2t.cli.app import main
from earl_m2t.model.elements import Link
from earl_m2t.model.variability import Structure, lingers, link_agents, system_links
from earl_m2t.verify.switching import Reconfiguration, reconfiguration

SAMPLES = ("harmoniser", "two_arm")
SWITCH_PROVEN = ("no switch loses values", "every switch can end without its timeout", "exclusivity: ",
                 "no leaving agent's send is dropped: what a leaving agent sends until it stops reaches its receiver")
_TOKEN = re.compile(r"\s*(&&|\|\||==|!|\(|\)|\w+)")


def _evaluate(condition: str, values: dict[str, int]) -> bool:
    """The value of a Promela condition of globals, ``&&``, ``||``, ``!``, ``==`` and parentheses."""
    words = []
    for token in _TOKEN.findall(condition):
        words.append({"&&": "and", "||": "or", "!": "not", "true": "True", "false": "False"}.get(token, token))
        if token[0].isalpha() and token not in ("true", "false"):
            words[-1] = repr(values[token])
    assert "".join(_TOKEN.findall(condition)) == condition.replace(" ", ""), condition  # every token read
    return bool(eval(" ".join(words), {"__builtins__": {}}))  # noqa: S307 - the tokens above only


def _globals(rc: Reconfiguration) -> list[dict[str, int]]:
    """Every value of cfg, nxt, switching and each variable agent's leaving and active."""
    names = ["switching", *(name for a in rc.agents for name in (a.leaving, a.active))]
    numbers = range(len(rc.structures))
    return [{"cfg": cfg, "nxt": nxt, **dict(zip(names, flags))}
            for cfg, nxt in product(numbers, numbers) for flags in product((0, 1), repeat=len(names))]


def _expected(rc: Reconfiguration, link: Link, values: dict[str, int]) -> tuple[bool, bool]:
    """Whether a send on ``link`` is delivered, and whether it is dropped, as the switch design says."""
    before, after = rc.structures[values["cfg"]], rc.structures[values["nxt"]]
    sender = rc.agent(link_agents(rc.system, link)[0])
    draining = sender is not None and bool(values[sender.leaving] and values[sender.active])
    held = before.has_link(link.path)
    delivered = held and (not values["switching"] or after.has_link(link.path)
                          or (draining and lingers(rc.system, link, before, after)))
    return delivered, bool(values["switching"]) and draining and held and not delivered


def _agrees_with_the_design(rc: Reconfiguration) -> list[str]:
    """Checks every variable link's conditions for every value of the globals; the links that linger."""
    links = [link for link in system_links(rc.system) if link.path in rc.varying]
    for link in links:
        opened, drops = rc.link_open(link), rc.link_drops(link)
        assert opened is not None
        for values in _globals(rc):
            delivered, dropped = _expected(rc, link, values)
            assert _evaluate(opened, values) == delivered, (link.path, values, opened)
            assert (drops is not None and _evaluate(drops, values)) == dropped, (link.path, values, drops)
    return [link.path for link in links
            if any(lingers(rc.system, link, b, a) for b, a in product(rc.structures, repeat=2))]


@pytest.mark.parametrize("sample", SAMPLES)
def test_a_variable_link_delivers_exactly_when_the_design_says(sample: str) -> None:
    rc = reconfiguration(load(SAMPLE_FILES[sample]["sysml"]).model)
    assert rc is not None
    assert _agrees_with_the_design(rc), "no link of the sample lingers: the test would decide nothing"


def test_so_it_does_in_drawn_structures_of_the_harmoniser() -> None:
    """Configurations drawn over the harmoniser's agents and variable links (an agent or a link
    in some and not others, a link held where its receiver is absent): a link that lingers from
    some of the configurations holding it only, towards different next ones, too."""
    rc = reconfiguration(load(SAMPLE_FILES["harmoniser"]["sysml"]).model)
    assert rc is not None
    draw = random.Random(9)
    agents, links = sorted(a.path for a in rc.system.agents), sorted(rc.varying)
    told_apart = 0
    for _ in range(40):
        drawn = tuple(Structure(rc.structures[n % len(rc.structures)].configuration,
                                frozenset(a for a in agents if draw.random() < 0.6),
                                frozenset(link for link in links if draw.random() < 0.5))
                      for n in range(draw.choice((3, 4))))
        varied = replace(rc, structures=drawn)
        _agrees_with_the_design(varied)
        told_apart += any("cfg ==" in varied.lingering(link) for link in system_links(rc.system)
                          if link.path in rc.varying)
    assert told_apart, "no drawn link lingers from some configurations only"


def test_the_evaluator_reads_promela_as_promela() -> None:
    values = {"cfg": 1, "nxt": 0, "switching": 1, "leaving0": 1, "active0": 0}
    assert _evaluate("(cfg == 1) && (!switching || nxt == 1 || leaving0 && active0 && nxt == 0)", values) is False
    assert _evaluate("!(cfg == 0) && (switching || false)", values) is True
    assert _evaluate("true", values) and not _evaluate("false", values)


def _closed_at_the_decision(self: Reconfiguration, link: Link) -> str | None:
    """The condition of a variable link before lingering links: closed when the switch is decided."""
    if link.path not in self.varying:
        return None
    held = self.holds(link)
    if not held:
        return "false"
    now = " || ".join(f"cfg == {i}" for i in held)
    then = " || ".join(f"nxt == {i}" for i in held)
    return f"({now}) && (!switching || {then})"


def _verify(capsys: pytest.CaptureFixture[str], *arguments: str) -> tuple[int, dict]:
    code = main(["verify", *arguments, "--format", "json"])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("sample", SAMPLES)
def test_the_samples_prove_that_no_leaving_agent_s_send_is_dropped(
    sample: str, capsys: pytest.CaptureFixture[str],
) -> None:
    code, result = _verify(capsys, str(SAMPLE_FILES[sample]["sysml"]))
    assert code == 0 and result["findings"] == [] and result["not_proven"] == [], result
    assert all(any(line.startswith(text) for line in result["proven"]) for text in SWITCH_PROVEN), result["proven"]


def test_closed_at_the_decision_the_harmoniser_drops_guide_s_last_command(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
) -> None:
    """The old design fails V009: guide/a, leaving, sends its task command to tiago/a, which
    stays, on a link already closed; V006-V008 do not see it."""
    monkeypatch.setattr(Reconfiguration, "link_open", _closed_at_the_decision)
    code, result = _verify(capsys, str(SAMPLE_FILES["harmoniser"]["sysml"]))

    assert code == 1
    (finding,) = result["findings"]
    assert finding["code"] == "V009" and finding["element"] == "guide/a,tiago/a", finding
    assert "guide/a sends on it while the switch guiding → " in finding["message"], finding
    assert "the value goes nowhere" in finding["message"]
    last = finding["trace"][-1]
    assert (last["subsystem"], last["from"], last["to"]) == ("guide/a,tiago/a", "sent", "dropped"), last
    assert last["by"].startswith("the closed link: guide/a leaves in the switch guiding → "), last
    assert finding["trace"][-2]["subsystem"] == "guide/a.cs"  # the iteration that sent it, shown before
    assert all(any(line.startswith(text) for line in result["proven"]) for text in SWITCH_PROVEN[:3]), result


def test_check_v009_alone_finds_the_drop_on_the_two_arm_sample(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.setattr(Reconfiguration, "link_open", _closed_at_the_decision)
    code, result = _verify(capsys, str(SAMPLE_FILES["two_arm"]["sysml"]), "--check", "V009")
    assert code == 1 and [(f["code"], f["element"]) for f in result["findings"]] == [("V009", "manipA/a,task/a")]
    assert result["proven"] == []


def test_closed_at_the_decision_the_task_waits_for_a_status_the_leaving_manipulator_sent(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
) -> None:
    """The hand-over fixture whose task waits for a status in withB (test_verify_variability's
    PER_LINK): the status manipA/a sends while it drains the command that began the switch is
    the one withB waits for; dropped, the system deadlocks."""
    monkeypatch.setattr(Reconfiguration, "link_open", _closed_at_the_decision)
    code, result = _verify(capsys, str(_variant(tmp_path, PER_LINK)), "--force")
    assert code == 1 and {f["code"] for f in result["findings"]} == {"V002", "V009"}, result["findings"]
    deadlock = next(f for f in result["findings"] if f["code"] == "V002")
    assert "task/a.cs in withB waits for status/ib" in deadlock["message"], deadlock


def test_a_leaving_agent_s_send_to_an_agent_leaving_too_is_dropped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str],
) -> None:
    """The harmoniser with tiago/a in guiding only: at the switch guiding → fallResponse both
    guide/a and tiago/a leave, so their link closes at the decision and what guide/a sends while
    it drains goes nowhere."""
    source = SAMPLE_FILES["harmoniser"]["sysml"].read_text(encoding="utf-8")
    old = 'metadata guiding : Structure { agents = "guide/a";'
    assert old in source
    path = tmp_path / "both_leave.sysml"
    path.write_text(source.replace(old, 'metadata guiding : Structure { agents = "guide/a tiago/a";'), encoding="utf-8")
    code, result = _verify(capsys, str(path), "--force", "--check", "V009")
    assert code == 1, result
    (finding,) = result["findings"]
    assert (finding["code"], finding["element"]) == ("V009", "guide/a,tiago/a"), finding
    assert "guide/a sends on it while the switch guiding → fallResponse is pending" in finding["message"]

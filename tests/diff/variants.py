"""Variants of the reference sample, each one edit as a modeller makes it in Papyrus."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples" / "pick_and_place"
SAMPLE = SAMPLES / "pick_and_place.uml"

IDLE_STATE = 'xmi:id="_rXzUTEyiuXPwTQS62wjGBA" name="idle"'
GUARD = "<body>newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun</body>"
LINK = re.compile(r' *<ownedConnector xmi:type="uml:Connector" xmi:id="_fW4SsBaHelMyrFWnRP6xWA" '
                  r'name="cs,fingerController/ve">.*?</ownedConnector>\n', re.S)
FINGER_CONTROLLER = "_38QkBCImyxlfHYOlvIzb7g"  # the part grip/a.fingerController/ve


def sample_text() -> str:
    return SAMPLE.read_text(encoding="utf-8")


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def renamed_state(text: str) -> str:
    assert IDLE_STATE in text
    return text.replace(IDLE_STATE, IDLE_STATE.replace('"idle"', '"waiting"'))


def with_guard_body(text: str, body: str) -> str:
    """The sample with ``body`` (XML text) as the guard of manip/a.cs's idle,jointMove/t."""
    start = text.index('name="idle,jointMove/t"')
    at = text.index(GUARD, start)
    return text[:at] + f"<body>{body}</body>" + text[at + len(GUARD):]


def changed_guard(text: str) -> str:
    """idle,jointMove/t no longer waits for the emergency stop to be released."""
    return with_guard_body(text, "newJointPos/pp.fun")


ESTOP_LATCHES = "<body>[] (manip/a.cs@emergencyStop -> [] manip/a.cs@emergencyStop)</body>"


def weakened_property(text: str) -> str:
    """estopLatches no longer says the emergency stop latches, only that it is left for idle."""
    assert text.count(ESTOP_LATCHES) == 1
    return text.replace(ESTOP_LATCHES, "<body>[] (manip/a.cs@emergencyStop -> &lt;&gt; manip/a.cs@idle)</body>")


def with_model_comment(text: str, xmi_id: str, body: str) -> str:
    """The Papyrus sample with a comment of the model whose ``<body>`` element is ``body``."""
    model = text.index("<uml:Model")
    end = text.index(">", model) + 1
    return (text[:end] + f'\n    <ownedComment xmi:type="uml:Comment" xmi:id="{xmi_id}">{body}</ownedComment>'
            + text[end:])


def property_comment_added(text: str) -> str:
    """A second property, as an ``earl-m2t: ltl`` comment of the model."""
    return with_model_comment(text, "_ltlCommentAddedInTheVariant",
                              "<body>earl-m2t: ltl taskSettles: &lt;&gt; task/a.cs@supervise</body>")


def changed_priority(text: str) -> str:
    """idle,emergencyStop/t (the first with priority 2) gets priority 3."""
    old = 'base_Transition="_lXeK7HEi-YLOWkH1lRRG-g" priority="2"'
    assert old in text
    return text.replace(old, old.replace('"2"', '"3"'))


def added_link(text: str) -> str:
    """A second link from grip/a.cs.fingerCommand/ob to the finger controller, named commandCopy."""
    match = LINK.search(text)
    assert match
    copy = (match.group(0).replace("_fW4SsBaHelMyrFWnRP6xWA", "_commandCopyLink00000000")
            .replace("_VMYupY3KM6MxwKkK-dbotw", "_commandCopyEnd1")
            .replace("_7BTMmFBR4aOowAUNqQvU4A", "_commandCopyEnd2")
            .replace('name="cs,fingerController/ve"', 'name="commandCopy"'))
    return text[:match.end()] + copy + text[match.end():]


def removed_subsystem(text: str) -> str:
    """grip/a.fingerController/ve deleted with its four connectors."""
    text = re.sub(r' *<ownedConnector [^>]*>(?:(?!</ownedConnector>).)*' + FINGER_CONTROLLER
                  + r'(?:(?!</ownedConnector>).)*</ownedConnector>\n', "", text, flags=re.S)
    return re.sub(r' *<ownedAttribute [^>]*name="fingerController/ve"[^>]*/>\n', "", text)


def resaved(text: str) -> str:
    """What a tool's re-save can do: every XMI id new, other indentation; the model is the same.
    (EA's ids of its language types, ``EAJava_Boolean``, are type names and stay.)"""
    ids = [i for i in dict.fromkeys(re.findall(r'xmi:id="([^"]+)"', text)) if not i.startswith("EAJava_")]
    renamed = {old: f"_resaved{n:06d}" for n, old in enumerate(ids)}
    text = re.sub(r'(?<=["\s])(' + "|".join(re.escape(i) for i in sorted(ids, key=len, reverse=True)) + r')(?=["\s])',
                  lambda m: renamed[m.group(1)], text)
    return "\n".join("  " + line if line[:1].isspace() else line for line in text.split("\n"))


def renamed_pf(text: str) -> str:
    """grip/a.fingerController/ve's regulateFinger/pf renamed to regulateFingers/pf (its call too)."""
    assert text.count('name="regulateFinger/pf"') == 2
    return text.replace('name="regulateFinger/pf"', 'name="regulateFingers/pf"')


def renamed_replicated_pf(text: str) -> str:
    """regulateMotor/pf of the MotorController block, which manip/a holds six times, renamed to regulate/pf."""
    assert text.count('name="regulateMotor/pf"') == 2
    return text.replace('name="regulateMotor/pf"', 'name="regulate/pf"')

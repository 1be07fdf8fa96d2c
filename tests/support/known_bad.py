"""Known-bad variants of the samples, for the tests that show a loaded campaign catches what it
exists to catch within the runs it keeps (tests/support/campaign.py).

The pick_and_place campaigns check that task/a's one-shot jointMove setpoint reaches manip/a.cs
in every loaded run: the model queues manip/a.cs's commands (a queue of 8) and activates it by
them. :func:`one_shot_into_latest_value` is the model as rule C009 warns against: the commands
kept as the latest value only and manip/a.cs on its own clock, so a setpoint that a newer command
overwrites before manip/a.cs iterates again is lost, which only the timing of a loaded run shows.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

from tests.support.paths import ROOT

PICK_AND_PLACE = ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml"

QUEUED_COMMANDS = """\
            port 'manipulatorCommand/ib' : InputBuffer {
                attribute :>> msg : DataTypes::ManipulatorCommand;
                @Receive { receive = ReceiveMode::queue; queueSize = 8; }
            }
"""
LATEST_COMMANDS = ("            port 'manipulatorCommand/ib' : InputBuffer "
                   "{ attribute :>> msg : DataTypes::ManipulatorCommand; }\n")
COMMAND_GROUP = ('            metadata commands : Group { obligatory = "manipulatorCommand/ib"; '
                 'optional = "motorControllerStateK/ib"; }\n')
# How long after manip/a.cs started it may take to enter jointMove before the setpoint counts as
# lost. Every runtime starts the subsystems together (the ROS targets behind their start barrier):
# task/a.cs sends the setpoint in its first iteration, and manip/a.cs enters jointMove within
# milliseconds, within a second on a loaded machine.
GRACE_SECONDS = 5.0
ACTIVATION = ('                    @Activation { bufferGroup = "commands"; minPeriod = 0.0005; firstTimeout = 0.1; '
              'nextTimeout = 0.02; }\n')


def one_shot_into_latest_value(folder: Path, text: str | None = None) -> Path:
    """``folder/pick_and_place.sysml``: the sample (or its SysML v2 ``text``) with manip/a.cs's
    commands a latest-value input and no buffer group activating it (finding C009, a warning)."""
    text = PICK_AND_PLACE.read_text(encoding="utf-8") if text is None else text
    for old, new, count in ((QUEUED_COMMANDS, LATEST_COMMANDS, 1), (COMMAND_GROUP, "", 1), (ACTIVATION, "", 4)):
        assert text.count(old) == count, f"the sample no longer holds {old.strip()!r} {count} time(s)"
        text = text.replace(old, new)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "pick_and_place.sysml"
    path.write_text(text, encoding="utf-8")
    return path


class SetpointWatch:
    """A ``seen`` for tests/support/load.py's ``run_until``: holds once manip/a.cs reached
    emergencyStop, or once GRACE_SECONDS passed since it started without entering jointMove:
    the setpoint is lost, and the run would only wait for its timeout to show the same.
    ``states`` gives the states manip/a.cs entered, its initial one first."""

    def __init__(self, states: Callable[[list[str]], list[str]]) -> None:
        self.states = states
        self.started: float | None = None

    def __call__(self, lines: list[str]) -> bool:
        entered = self.states(lines)
        if "emergencyStop" in entered:
            return True
        if self.started is None and entered:
            self.started = time.monotonic()
        waited = time.monotonic() - self.started if self.started is not None else 0.0
        return "jointMove" not in entered and waited > GRACE_SECONDS

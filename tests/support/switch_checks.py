"""The checks of the two variable-structure samples' runs, whatever runs them (the C++ system
executor, a ROS launch): ``samples/two_arm`` hands numbered commands over between two arms,
``samples/harmoniser`` stops and resumes its guide agent around a fall. A switch line reads
"switch A -> B in N cycles" (deterministic) or "in X.XXX ms" (on the clock)."""

from __future__ import annotations

import re
import shutil
import statistics
from collections import Counter
from pathlib import Path

from tests.support.cpp_sample import cmake_build, generate_with_user_code
from tests.support.cpp_sample import run as run_cpp

SWITCH = re.compile(r"^switch (\w+) -> (\w+) in (\d+(?:\.\d+)?) (cycles|ms)( \(forced\))?$")


def switches(lines: list[str]) -> list[tuple[str, str]]:
    """The switches of a run, in order: (from, to)."""
    return [(m.group(1), m.group(2)) for m in map(SWITCH.match, lines) if m]


def latencies_ms(lines: list[str]) -> list[float]:
    """The latency of every switch measured on the clock, in ms."""
    return [float(m.group(3)) for m in map(SWITCH.match, lines) if m and m.group(4) == "ms"]


def latency_summary(latencies: list[float]) -> str:
    """'N switches, median X ms, worst Y ms'."""
    if not latencies:
        return "no switch"
    return f"{len(latencies)} switches, median {statistics.median(latencies):.3f} ms, worst {max(latencies):.3f} ms"


def undelivered(lines: list[str]) -> list[str]:
    return [line for line in lines if "undelivered at switch" in line or "overflowed" in line]


def notable(lines: list[str]) -> str:
    """What a failed launch said of the switch, errors and deaths, and its end."""
    said = [line for line in lines if re.search(r"^switch |undelivered|WARN|ERROR|died|manager", line)]
    return "\n".join(said[:40] + ["..."] + lines[-20:])


# ------------------------------------------------------------------ two_arm

# GuideAgent's tag reactivation = resume, and the line after it, in the harmoniser's SysML v2 file
GUIDE_RESUMES = ("            @AgentReactivation { reactivation = Reactivation::resume; }\n"
                 "            part cs : GuideControl;\n")


def restarted_harmoniser(folder: Path) -> Path:
    """samples/harmoniser (its SysML v2 file) with guide/a restarted instead of resumed, in
    ``folder``, its user code beside it: the known-bad variant of the harmoniser campaigns."""
    sample = Path(__file__).resolve().parents[2] / "samples" / "harmoniser"
    text = (sample / "harmoniser.sysml").read_text(encoding="utf-8")
    assert text.count(GUIDE_RESUMES) == 1
    folder.mkdir(parents=True, exist_ok=True)
    model = folder / "harmoniser.sysml"
    model.write_text(text.replace(GUIDE_RESUMES, "            part cs : GuideControl;\n"), encoding="utf-8")
    shutil.copytree(sample / "user", folder / "user")
    return model


def forced_two_arm(folder: Path) -> Path:
    """samples/two_arm (its SysML v2 file) with switchTimeout = 0.001 in ``folder``, its user code
    beside it: one millisecond, a coordinator cycle, forces every switch. gen needs --force
    (rule X009 says the timeout is below the drain bound, which is the point)."""
    sample = Path(__file__).resolve().parents[2] / "samples" / "two_arm"
    text = (sample / "two_arm.sysml").read_text(encoding="utf-8")
    assert text.count("switchTimeout = 0.1;") == 2
    model = folder / "two_arm.sysml"
    folder.mkdir(parents=True, exist_ok=True)
    model.write_text(text.replace("switchTimeout = 0.1;", "switchTimeout = 0.001;"), encoding="utf-8")
    shutil.copytree(sample / "user", folder / "user")
    return model


def forced_switches(lines: list[str]) -> int:
    """How many switch lines say the switch was forced."""
    return sum(1 for m in map(SWITCH.match, lines) if m and m.group(5))


class TwoArm:
    """task/a.cs sends 201 numbered commands and hands the job over between manipA/a and
    manipB/a 20 times; each arm prints the seq of every command it takes, task/a the arm it
    sent each one to."""

    COMMANDS = 201  # 10 per configuration before each of the 20 hand-overs, then one more
    SWITCHES = 20
    TIMEOUT_MS = 100.0  # the switchTimeout of useA and useB

    SENT = re.compile(r"^task/a\.cs: sent seq (\d+) to (manip[AB]/a)$")
    TOOK = re.compile(r"^(manip[AB]/a)\.cs: took seq (\d+)$")
    RESET = re.compile(r"^(manip[AB]/a)\.cs: reset before seq (\d+)$")
    FINISHED = re.compile(r"^step \d+ task/a\.cs: with[AB] -> finished ")
    NAMED = re.compile(r"^link (task/a,manip[AB]/a): seq (\d+) undelivered at switch$")
    COUNTED = re.compile(r"^link (task/a,manip[AB]/a): (\d+) value\(s\) undelivered at switch$")

    @classmethod
    def problems(cls, lines: list[str]) -> list[str]:
        """What the run shows against the checks: every numbered command taken exactly once,
        by the arm of the configuration it was sent in; no value undelivered at a switch and
        no queue overflowed; 20 switches, each within the switchTimeout. Empty when it passes."""
        sent: dict[int, str] = {}
        found: list[str] = []
        for match in filter(None, map(cls.SENT.match, lines)):
            seq, arm = int(match.group(1)), match.group(2)
            if seq in sent:
                found.append(f"seq {seq} sent twice")
            sent[seq] = arm
        if sorted(sent) != list(range(1, cls.COMMANDS + 1)):
            found.append(f"{len(sent)} numbered commands sent, not 1..{cls.COMMANDS}")
        taken: dict[int, list[str]] = {}
        for match in filter(None, map(cls.TOOK.match, lines)):
            taken.setdefault(int(match.group(2)), []).append(match.group(1))
        for seq, arm in sorted(sent.items()):
            arms = taken.get(seq, [])
            if arms != [arm]:
                found.append(f"seq {seq} sent to {arm}, taken by {arms or 'none'}")
        found += [f"taken but never sent: {seq}" for seq in sorted(set(taken) - set(sent))]
        matches = [m for m in map(SWITCH.match, lines) if m]
        if len(matches) != cls.SWITCHES:
            found.append(f"{len(matches)} switches")
        found += [f"{m.group(0)}: beyond {cls.TIMEOUT_MS} ms" for m in matches if float(m.group(3)) > cls.TIMEOUT_MS]
        found += undelivered(lines)
        found += cls.not_reset_at_restart(lines)
        return found[:12]

    @classmethod
    def not_reset_at_restart(cls, lines: list[str]) -> list[str]:
        """Each arm's pfs are reset every time it (re)starts, before its first command:
        moveArm/pf prints ``reset before seq N`` then. manipA/a starts in useA and restarts at
        each switch to useA, manipB/a at each switch to useB; each gets commands every time."""
        joined = {"manipA/a": 1 + sum(1 for _, to in switches(lines) if to == "useA"),
                  "manipB/a": sum(1 for _, to in switches(lines) if to == "useB")}
        resets = Counter(m.group(1) for m in map(cls.RESET.match, lines) if m)
        return [f"{arm} started {count} time(s), its pfs were reset before {resets[arm]} of them"
                for arm, count in joined.items() if resets[arm] != count]

    @classmethod
    def unreconciled(cls, lines: list[str]) -> list[str]:
        """What a run with forced switches shows against "every command is taken or reported":
        each numbered command sent is either taken once, by the arm it was sent to, or named
        undelivered at a switch, on the link to that arm (``link task/a,manipA/a: seq 10
        undelivered at switch``), never both, and the counts of the switches' reports add up
        to the values they name. Empty when every command is accounted for."""
        sent = {int(m.group(1)): m.group(2) for m in map(cls.SENT.match, lines) if m}
        taken: dict[int, list[str]] = {}
        for match in filter(None, map(cls.TOOK.match, lines)):
            taken.setdefault(int(match.group(2)), []).append(match.group(1))
        named: dict[int, list[str]] = {}
        for match in filter(None, map(cls.NAMED.match, lines)):
            named.setdefault(int(match.group(2)), []).append(match.group(1))
        counted = sum(int(m.group(2)) for m in map(cls.COUNTED.match, lines) if m)
        found: list[str] = []
        if sorted(sent) != list(range(1, cls.COMMANDS + 1)):
            found.append(f"{len(sent)} numbered commands sent, not 1..{cls.COMMANDS}")
        for seq, arm in sorted(sent.items()):
            fates = ([f"taken by {a}" for a in taken.get(seq, [])]
                     + [f"reported on {link}" for link in named.get(seq, [])])
            if fates not in ([f"taken by {arm}"], [f"reported on task/a,{arm}"]):
                found.append(f"seq {seq} sent to {arm}: {', '.join(fates) or 'lost, neither taken nor reported'}")
        if counted != sum(len(links) for links in named.values()):
            found.append(f"the switches counted {counted} undelivered values and named "
                         f"{sum(len(links) for links in named.values())}")
        return found[:12]

    @classmethod
    def finished(cls, lines: list[str]) -> bool:
        """task/a has finished and the last command was taken."""
        return any(cls.FINISHED.match(line) for line in lines) and any(
            line.endswith(f"took seq {cls.COMMANDS}") for line in lines)


# ------------------------------------------------------------------ harmoniser

class Harmoniser:
    """The scripted lidar sees the person fall once and get up again: tha/a switches guiding ->
    fallResponse -> guiding; guide/a (reactivation resume) parks in waiting and goes on from
    there, fallHelp/a starts from its initial state."""

    SWITCHES = [("none", "guiding"), ("guiding", "fallResponse"), ("fallResponse", "guiding")]
    TIMEOUT_MS = 500.0  # the switchTimeout of every configuration

    LEAD = re.compile(r"^guide/a\.cs: lead to waypoint (\d+) \(command (\d+)\)$")
    PARK = re.compile(r"^guide/a\.cs: park after command (\d+)$")
    ASSIST = re.compile(r"^fallHelp/a\.cs: assist step (\d+) \(command (\d+)\)$")
    STAND_BY = re.compile(r"^fallHelp/a\.cs: stand by after command (\d+)$")
    TOOK = re.compile(r"^tiago/a\.cs: took command (\d+)$")
    GUIDE_STEP = re.compile(r"^step (\d+) guide/a\.cs: (\w+) -> (\w+) ")
    GUIDE = re.compile(r"^(?:step \d+ )?guide/a\.cs: ")
    GUIDE_START = re.compile(r"^step \d+ guide/a\.cs: start in ")  # its initial state entered
    FALL_HELP = re.compile(r"^(?:step \d+ )?fallHelp/a\.cs: ")

    @classmethod
    def resumed_at(cls, trace: list[str]) -> tuple[int, int]:
        """(the line of the switch to fallResponse, the first line of the guide agent back):
        its first line after that switch, or the switch back to guiding if it comes first. The
        agents of a ROS launch are processes of their own: a joining agent runs its first
        iteration before the coordinator, a message later, prints the switch."""
        fall = next(i for i, line in enumerate(trace) if SWITCH.match(line) and "-> fallResponse" in line)
        back = next(i for i, line in enumerate(trace) if SWITCH.match(line) and "fallResponse -> guiding" in line)
        first = next((i for i in range(fall + 1, back) if cls.GUIDE.match(trace[i])), back)
        return fall, first

    @classmethod
    def assert_resumed(cls, trace: list[str]) -> None:
        """Asserts that guide/a, resumed after the fall, goes on from its state and memory."""
        fall, back = cls.resumed_at(trace)
        before, after = trace[:fall], trace[back:]

        # the waypoints carry on: 1, 2, … up to the fall, then the next one, never 1 again
        waypoints_before = [int(m.group(1)) for m in map(cls.LEAD.match, before) if m]
        waypoints_after = [int(m.group(1)) for m in map(cls.LEAD.match, after) if m]
        assert waypoints_before == list(range(1, len(waypoints_before) + 1)) and len(waypoints_before) > 1
        assert waypoints_after[0] == waypoints_before[-1] + 1
        assert waypoints_after == list(range(waypoints_after[0], waypoints_after[0] + len(waypoints_after)))
        # stopped while fallResponse holds: back only once fallHelp/a, which held it, has stopped
        assert [line for line in trace[fall:back] if cls.ASSIST.match(line)]
        assert not [line for line in after if cls.FALL_HELP.match(line)]

        # its FSM: leaving() took it from leading to waiting, and it resumes in waiting at its next
        # step. Over a transport the leaving agent learns that it may stop (its links drained)
        # a few iterations later: the ones it ran in waiting (each a park) count as its steps.
        guide_steps = [(int(m.group(1)), m.group(2), m.group(3)) for m in map(cls.GUIDE_STEP.match, trace) if m]
        stopped = next((s for s in guide_steps if s[1:] == ("leading", "waiting")), None)
        assert stopped is not None
        at = next(i for i, line in enumerate(trace) if cls.GUIDE_STEP.match(line) and
                  (int(cls.GUIDE_STEP.match(line).group(1)), "leading", "waiting") == stopped)  # type: ignore[union-attr]
        parked = [int(m.group(1)) for m in map(cls.PARK.match, trace[at:fall]) if m]
        assert parked == list(range(stopped[0] + 1, stopped[0] + 1 + len(parked)))
        resumed = [s for s in guide_steps if s[0] > stopped[0]]
        assert resumed[0] == (stopped[0] + len(parked) + 1, "waiting", "leading")
        assert not any(cls.GUIDE_START.match(line) for line in after)

        # its memory: the resumed park (in waiting, where it stopped) numbers its command after the
        # ones sent before the fall
        commands_before = waypoints_before[-1] + 1 + len(parked)  # the first park, one per waypoint, the parks
        (first_park_after, *_) = [int(m.group(1)) for m in map(cls.PARK.match, after) if m]
        assert first_park_after == commands_before + 1

    @classmethod
    def problems(cls, lines: list[str]) -> list[str]:
        """What a run shows against every check of the sample: the three switches, each within
        the switchTimeout, nothing undelivered, fallHelp/a from its first step, guide/a resumed
        from its state and memory. Empty when it passes."""
        found: list[str] = []
        if switches(lines) != cls.SWITCHES:
            found.append(f"switches {switches(lines)}, not {cls.SWITCHES}")
        found += [f"{m.group(0)}: beyond {cls.TIMEOUT_MS} ms" for m in map(SWITCH.match, lines)
                  if m and m.group(4) == "ms" and float(m.group(3)) > cls.TIMEOUT_MS]
        found += undelivered(lines)
        found += cls.commands_not_taken_once(lines)
        # fallHelp/a starts from its initial state: it stands by with its first command, and
        # assists (as long as the person lies: none when the switch took that long) from step 1
        stand_by = [int(m.group(1)) for m in map(cls.STAND_BY.match, lines) if m]
        steps = cls.assist_steps(lines)
        if stand_by[:1] != [1] or steps != list(range(1, len(steps) + 1)):
            found.append(f"fallHelp/a did not start from its initial state: stood by after {stand_by[:2]}, "
                         f"assisted in steps {steps[:5]}")
        if not found:
            try:
                cls.assert_resumed(lines)
            except (AssertionError, StopIteration, ValueError, IndexError) as error:
                found.append(f"guide/a did not go on from its state and memory: {error or type(error).__name__}")
        return found

    @classmethod
    def commands_sent(cls, lines: list[str]) -> tuple[list[int], list[int]]:
        """The numbers of the commands guide/a and fallHelp/a printed sending (each pf that sends
        one prints its number)."""
        guide = [int(m.group(m.lastindex or 1)) for line in lines
                 for m in (cls.LEAD.match(line), cls.PARK.match(line)) if m]
        fall_help = [int(m.group(m.lastindex or 1)) for line in lines
                     for m in (cls.ASSIST.match(line), cls.STAND_BY.match(line)) if m]
        return guide, fall_help

    @classmethod
    def taken_runs(cls, lines: list[str]) -> list[list[int]]:
        """The numbers of the commands tiago/a took, in runs of consecutive ones."""
        runs: list[list[int]] = []
        for seq in (int(m.group(1)) for m in map(cls.TOOK.match, lines) if m):
            if runs and seq == runs[-1][-1] + 1:
                runs[-1].append(seq)
            else:
                runs.append([seq])
        return runs

    @classmethod
    def commands_not_taken_once(cls, lines: list[str]) -> list[str]:
        """tiago/a takes every command of the task agents once and in order, those a leaving agent
        sends in its last iterations (until it stops) included: guide/a's 1 … a, then every one
        fallHelp/a sent, then guide/a's a + 1 on (its numbering resumes; the run may end before
        its last ones are taken). tiago/a's lines are in its own order, whatever process printed
        the others."""
        runs = cls.taken_runs(lines)
        shown = ", ".join(f"{run[0]}…{run[-1]}" for run in runs)
        _, fall_help = cls.commands_sent(lines)
        if len(runs) != 3 or runs[0][0] != 1 or runs[1][0] != 1 or runs[2][0] != runs[0][-1] + 1:
            return [f"tiago/a took the task commands {shown}, not guide/a's 1…a, fallHelp/a's 1…b, guide/a's a+1…"]
        # guide/a's last lines may not be read yet when a launch ends: its count is no bound
        if runs[1][-1] != max(fall_help, default=0):
            return [f"tiago/a took the task commands {shown}; fallHelp/a sent 1…{max(fall_help, default=0)}"]
        return []

    @classmethod
    def first_waypoint_back(cls, trace: list[str]) -> int:
        """The first waypoint guide/a leads to once back."""
        _, back = cls.resumed_at(trace)
        return int(next(m for m in map(cls.LEAD.match, trace[back:]) if m).group(1))

    @classmethod
    def assist_steps(cls, trace: list[str]) -> list[int]:
        return [int(m.group(1)) for m in map(cls.ASSIST.match, trace) if m]


def cpp_trace(model: Path, folder: Path, target: str, cycles: int) -> list[str]:
    """The C++ target's deterministic run of ``model`` (its shipped user code)."""
    out = generate_with_user_code(model, model.parent / "user", folder / "out")
    return run_cpp(cmake_build(out, target), "--cycles", str(cycles)).splitlines()


def switch_timeouts_ms(ws: Path) -> dict[str, float]:
    """The switchTimeout of every configuration (ms), as the generated System holds it."""
    [system] = (ws / "src" / "earl" / "generated" / "include").glob("*/system.hpp")
    text = system.read_text(encoding="utf-8")
    names = re.search(r"kConfigurations\[\] = \{([^}]*)\}", text)
    timeouts = re.search(r"kSwitchTimeoutNs\[\] = \{([^}]*)\}", text)
    assert names is not None and timeouts is not None
    return {name.strip().strip('"'): int(ns) / 1e6
            for name, ns in zip(names.group(1).split(","), timeouts.group(1).split(","), strict=True)}


def beyond_timeout(lines: list[str], timeouts: dict[str, float]) -> list[str]:
    return [m.group(0) for m in map(SWITCH.match, lines) if m and float(m.group(3)) > timeouts[m.group(2)]]

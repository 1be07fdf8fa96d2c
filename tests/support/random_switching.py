"""Small variable-structure models drawn at random, for the differential test of ``verify``
against the generated C++ (tests/test_differential_switching.py).

A drawn model has a task agent and 1 to 3 worker agents (2 to 4 agents), 2 or 3 configurations
(each a set of workers, none at all too, and their links, the task agent's states naming one each), a queued or a
latest-value command link into each worker, and a worker FSM of an idle (quiescent) and a busy
state whose behaviour either takes the commands (``take/pf`` reads ``command/ib``) or leaves
them waiting (``hold/pf``), left on guards over ``newCommand/pp`` (a read of the commands),
``leaving()`` and a coin (``done/pp``, a memory the pf writes). A worker runs periodically or
on its commands (the commands obligatory or optional in its group, with or without a timeout).
The choices are the ones that decide what a leaving worker receives, which is what ``verify``
and the generated code must agree on.

The model is SysML v2 text (``tests/fixtures/differential/model.sysml.j2``) with its user code
(``user/``): the pfs print what they send and take, and toss coins seeded by ``EARL_DIFF_SEED``,
so each seed is another run of the same model.
"""

from __future__ import annotations

import random
import shutil
from dataclasses import dataclass, replace
from itertools import combinations
from pathlib import Path

import jinja2

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "differential"
# guards leaving idle and leaving busy (SysML v2 expressions); every one that leaves idle holds
# back while leaving() or waits for a command, so a leaving worker settles in idle
IDLE_EXITS = ("'newCommand/pp'() and not leaving()", "not leaving()", "'newCommand/pp'()")
BUSY_EXITS = ("leaving() or not 'newCommand/pp'()", "leaving()", "'done/pp'()", "leaving() or 'done/pp'()")
# the same guards in a worker every configuration holds, where leaving() is always false (rule X011)
STAYING = {"'newCommand/pp'() and not leaving()": "'newCommand/pp'()", "not leaving()": "true",
           "leaving() or not 'newCommand/pp'()": "not 'newCommand/pp'()", "leaving()": "'done/pp'()",
           "leaving() or 'done/pp'()": "'done/pp'()"}
SWITCH_TIMEOUT = 0.2  # s: 200 cycles of the deterministic run, far beyond a drain of 8 commands


@dataclass(frozen=True)
class WorkerState:
    name: str
    next: str
    pf: str  # "take" reads the commands, "hold" leaves them
    leave: str  # the guard of its one transition, and its behaviour's tc
    quiescent: bool


@dataclass(frozen=True)
class Worker:
    number: int
    reactivation: str  # "resume" or "restart"
    queue_size: int  # 0: latest value
    group: str  # "": periodic; "obligatory" or "optional": run on the commands
    next_timeout: float  # with a group: 0 waits for ever, else runs after this long without one
    done_one_in: int
    states: tuple[WorkerState, ...]

    @property
    def agent(self) -> str:
        return f"w{self.number}/a"

    @property
    def ns(self) -> str:
        return f"w{self.number}_a"

    @property
    def links(self) -> tuple[str, str]:
        return f"task/a,{self.agent}", f"{self.agent},task/a"


@dataclass(frozen=True)
class Configuration:
    name: str
    state: str  # the task agent's state that names it
    next: str  # the state the task agent hands over to
    agents: tuple[str, ...]
    links: tuple[str, ...]


@dataclass(frozen=True)
class DrawnModel:
    seed: int
    workers: tuple[Worker, ...]
    configurations: tuple[Configuration, ...]
    commands_per_configuration: int
    hand_overs: int
    early_one_in: int
    switch_timeout: float = SWITCH_TIMEOUT

    @property
    def package(self) -> str:
        return f"Drawn{self.seed}"

    @property
    def executable(self) -> str:
        return f"{self.package}_system"

    def describe(self) -> str:
        """One line per worker and configuration, for a failure message."""
        lines = [f"seed {self.seed}: {self.commands_per_configuration} commands per configuration, "
                 f"{self.hand_overs} hand-overs"]
        for w in self.workers:
            how = f"on its commands ({w.group}{f', timeout {w.next_timeout}' if w.next_timeout else ''})" \
                if w.group else "periodic"
            kind = f"queue {w.queue_size}" if w.queue_size else "latest value"
            states = "; ".join(f"{s.name}{' (quiescent)' if s.quiescent else ''}: {s.pf}, leaves on {s.leave}"
                               for s in w.states)
            lines.append(f"  {w.agent} ({w.reactivation}, {kind}, {how}): {states}")
        lines += [f"  {c.name}: {' '.join(c.agents) or 'no worker'}" for c in self.configurations]
        return "\n".join(lines)


def draw(seed: int) -> DrawnModel:
    """The model of ``seed``: the same seed draws the same model."""
    rng = random.Random(seed)
    workers = tuple(_worker(rng, n) for n in range(1, rng.randint(1, 3) + 1))
    subsets = [c for k in range(len(workers) + 1) for c in combinations(workers, k)]
    picked = rng.sample(subsets, min(rng.randint(2, 3), len(subsets)))
    for w in workers:  # every worker in some configuration
        if not any(w in c for c in picked):
            picked[rng.randrange(len(picked))] += (w,)
    if len({frozenset(c) for c in picked}) < len(picked):  # alike after the fix-up: another draw
        return draw(seed + 1_000_003)
    chosen = [sorted(set(c), key=lambda w: w.number) for c in picked]
    staying = {w.number for w in workers if all(w in c for c in chosen)}
    workers = tuple(_staying(w) if w.number in staying else w for w in workers)
    chosen = [[workers[w.number - 1] for w in c] for c in chosen]
    count = len(chosen)
    configurations = tuple(
        Configuration(f"cfg{i}", f"with{i}", f"with{(i + 1) % count}", tuple(w.agent for w in c),
                      tuple(link for w in c for link in w.links))
        for i, c in enumerate(chosen))
    return DrawnModel(seed, workers, configurations, rng.randint(3, 8), rng.randint(3, 6), rng.choice((4, 8, 1000)))


def _worker(rng: random.Random, number: int) -> Worker:
    group = rng.choice(("", "obligatory", "optional"))
    # idle leaving its commands and held back by leaving() alone half the time: a leaving worker
    # that waits there for ever unless a state that takes them comes first
    states = (
        WorkerState("idle", "busy", rng.choice(("take", "hold")), rng.choice((IDLE_EXITS[1], *IDLE_EXITS)), True),
        WorkerState("busy", "idle", rng.choice(("take", "hold")), rng.choice(BUSY_EXITS), rng.random() < 0.25),
    )
    return Worker(number, rng.choice(("resume", "restart")), rng.choice((0, 4, 8)), group,
                  rng.choice((0.0, 0.005)) if group else 0.0, rng.choice((2, 3, 5)), states)


def _staying(worker: Worker) -> Worker:
    """``worker`` with the guards of one no switch removes."""
    return replace(worker, states=tuple(replace(s, leave=STAYING.get(s.leave, s.leave)) for s in worker.states))


def write(model: DrawnModel, folder: Path) -> Path:
    """``folder/model.sysml`` and its user code in ``folder/user/``: the model file."""
    environment = jinja2.Environment(loader=jinja2.FileSystemLoader(FIXTURES), undefined=jinja2.StrictUndefined,
                                     trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "model.sysml"
    path.write_text(environment.get_template("model.sysml.j2").render(m=model), encoding="utf-8")
    user = folder / "user"
    user.mkdir(exist_ok=True)
    shutil.copy(FIXTURES / "user" / "coin.hpp", user / "coin.hpp")
    send = user / "task_a" / "cs"
    send.mkdir(parents=True, exist_ok=True)
    (send / "send_pf.hpp").write_text(environment.get_template("user/send_pf.hpp.j2").render(m=model), encoding="utf-8")
    (send / "repeat_pf.hpp").write_text(environment.get_template("user/repeat_pf.hpp.j2").render(m=model),
                                        encoding="utf-8")
    for w in model.workers:
        own = user / w.ns / "cs"
        own.mkdir(parents=True, exist_ok=True)
        for pf in ("take", "hold"):
            text = environment.get_template(f"user/{pf}_pf.hpp.j2").render(m=model, w=w)
            (own / f"{pf}_pf.hpp").write_text(text, encoding="utf-8")
    return path

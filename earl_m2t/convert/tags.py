"""The tags of buffers, states and subsystems as SysML v2 metadata usages (``@Receive { … }``,
``@Activation { … }``, FABRIC's ``@InputBuffer { side = …; }``), for earl_m2t.convert.view."""

from __future__ import annotations

from earl_m2t.model.elements import Activation, Buffer, Simulation, State


def names_string(names: tuple[str, ...]) -> str:
    return '"' + " ".join(names) + '"'


def receive_tags(buffer: Buffer) -> list[str]:
    """``@Receive { … }`` of an Input Buffer that does not keep EARL's latest value."""
    if buffer.direction != "in" or (buffer.receive == "latest" and not buffer.queue_size):
        return []
    return [f"@Receive {{ receive = ReceiveMode::{buffer.receive}; queueSize = {buffer.queue_size}; }}"]


def buffer_tags(buffer: Buffer, concept: str) -> list[str]:
    """``@Receive { … }``, or with a reliability that is not EARL's default or FABRIC's side,
    converter and channel ``@InputBuffer { … }`` / ``@OutputBuffer { … }``, of a buffer port."""
    others = [f"reliability = Reliability::{buffer.reliability};"] if buffer.reliability != "reliable" else []
    others += [f"{tag} = {string_literal(value)};" for tag, value in (
        ("side", buffer.side), ("converter", buffer.converter), ("channel", buffer.channel)) if value]
    receive = receive_tags(buffer)
    if not others:
        return receive
    tags = ([f"receive = ReceiveMode::{buffer.receive};", f"queueSize = {buffer.queue_size};"] if receive else [])
    return [f"@{concept} {{ {' '.join(tags + others)} }}"]


def simulation_tags(simulation: Simulation | None, concept: str) -> list[str]:
    """``@ControlSubsystem { useRosSimClock = …; … }``: FABRIC's ``<simulation>`` of a subsystem."""
    if simulation is None:
        return []
    flags = [("useRosSimClock", simulation.use_ros_sim_clock), ("useSimClock", simulation.use_sim_clock),
             ("triggerGazebo", simulation.trigger_gazebo)]
    tags = " ".join(f"{tag} = {'true' if value else 'false'};" for tag, value in flags if value is not None)
    return [f"@{concept} {{ {tags} }}"]


def composition_tags(state: State) -> list[str]:
    """``@FsmState { behaviours = "…"; exclusiveGuards = true; }``: FABRIC's behaviours a state
    runs side by side, and guards that exclude each other by design."""
    tags = [f"behaviours = {names_string(state.composes)};"] if state.composes else []
    tags += ["exclusiveGuards = true;"] if state.exclusive_guards else []
    return [f"@FsmState {{ {' '.join(tags)} }}"] if tags else []


def activation_tags(activation: Activation) -> list[str]:
    """``@Activation { … }`` of a state that says when its subsystem iterates."""
    tags = [f'bufferGroup = "{activation.group}";'] if activation.group else []
    for tag, value in (("minPeriod", activation.min_period), ("firstTimeout", activation.first_timeout),
                       ("nextTimeout", activation.next_timeout), ("minPeriodSim", activation.min_period_sim),
                       ("firstTimeoutSim", activation.first_timeout_sim)):
        if value is not None:
            tags.append(f"{tag} = {value!r};")
    if activation.used_time:
        tags.append(f"usedTime = {string_literal(activation.used_time)};")
    return [f"@Activation {{ {' '.join(tags)} }}"] if tags else []


def string_literal(text: str) -> str:
    """A SysML v2 string literal."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'

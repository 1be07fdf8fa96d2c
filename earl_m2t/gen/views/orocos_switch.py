"""The variable-structure part of the Orocos view: how the components of a model with
configurations carry the switch of ``earl/switch_protocol.hpp``. None of it exists for a model
without configurations, whose output stays what it was.

Every connection is made once, by the deployer (docs/orocos-target.md, *Variable structure*):

* a variable link gets its own output port on its sending master and its own input port on
  its receiving master, both named ``<buffer port>__<link>``; the sender writes to it only
  while the link is open, the receiver hands what arrives to ``SwitchMember::deliver``;
* the coordinator's master writes every ``SwitchCommand`` on its output port ``earl_switch``,
  connected to the input port ``earl_switch`` of every other master, and reads every
  ``SwitchAck`` on its input port ``earl_switch_ack``, connected from the output port
  ``earl_switch_ack`` of every other master (buffer connections: RTT reads several connections
  into one input port one after the other, none lost).

A component type serves every instance of its definition, so an instance's part in the switch
(its node number, variable agent, control flag, whether it coordinates, its variable links)
is a set of component properties its deployer script sets before configureComponent.
"""

from __future__ import annotations

from typing import Any

from earl_m2t.gen.names import cpp_identifier
from earl_m2t.gen.views.switch_wiring import SwitchWiring
from earl_m2t.model.elements import Link

Data = dict[str, Any]

COMMAND_PORT = "earl_switch"
ACK_PORT = "earl_switch_ack"


def link_port(port: str, link: Link) -> str:
    """The port of one variable link on the master of its buffer ``port``."""
    return f"{port}__{cpp_identifier(link.name or link.path)}"


def definition_switch(wiring: SwitchWiring | None, cpp_system: Data, block_id: str,
                      blocks: dict[str, str]) -> Data | None:
    """What the component library of a definition needs: the generated System's header, the
    node count, whether the definition holds the coordinator. ``blocks``: instance path -> its
    definition's block id."""
    if wiring is None:
        return None
    switching = cpp_system["switching"]
    coordinator = next(n for n in wiring.nodes if n.coordinator)
    return {"include": cpp_system["main"]["include"], "system": cpp_system["main"]["cls"],
            "nodes": len(wiring.nodes), "initial": switching["initial"],
            "initial_comment": switching["initial_comment"],
            "coordinator": blocks[coordinator.path] == block_id}


def instance_switch(wiring: SwitchWiring | None, path: str, links: list[Data], master: str) -> Data | None:
    """An instance's properties: its node in the switch and the ports of its variable links
    (``<link> <buffer port> <link port>``, ``;``-separated, as configureHook reads them)."""
    if wiring is None:
        return None
    node = wiring.node(path)
    entries = []
    for link in links:
        if link.get("variable", -1) < 0:
            continue
        for end, port in (("from", "source_port"), ("to", "target_port")):
            component, _, link_port_name = link[end].partition(".")
            if component == master:
                entries.append(f"{link['variable']} {link[port]} {link_port_name}")
    return {"node": node.index, "agent": node.agent, "control": "true" if node.control else "false",
            "coordinator": "true" if node.coordinator else "false", "links": ";".join(entries)}


def control_connections(wiring: SwitchWiring | None, masters: dict[str, str]) -> list[Data]:
    """The command and acknowledgement connections between the coordinator's master and every
    other master (``masters``: instance path -> master component)."""
    if wiring is None:
        return []
    coordinator = masters[next(n for n in wiring.nodes if n.coordinator).path]
    connections: list[Data] = []
    for node in wiring.nodes:
        master = masters[node.path]
        if master == coordinator:
            continue
        connections += [{"from": f"{coordinator}.{COMMAND_PORT}", "to": f"{master}.{COMMAND_PORT}"},
                        {"from": f"{master}.{ACK_PORT}", "to": f"{coordinator}.{ACK_PORT}"}]
    return connections


def system_switch(wiring: SwitchWiring | None, masters: dict[str, str], queue: int) -> Data | None:
    """The deployment's control connections, each a buffer of ``queue``."""
    if wiring is None:
        return None
    return {"control": control_connections(wiring, masters), "queue": queue,
            "masters": [masters[n.path] for n in wiring.nodes]}


def fabric_variable_buffers(instance: Data, fixed: dict[str, str], variable: dict[str, list[str]]) -> None:
    """The superset in FABRIC's run-time configuration of ``instance``: an ``io_buffer`` per
    variable link into one of its Input Buffers (the channel its sender writes), beside the one
    of its links of every configuration (``fixed``: "<master>.<port>" -> channel). FABRIC's
    own deployer connects them all; it has no switch to open and close them."""
    port_of = {b["alias"]: b["port"] for b in instance["buffers"] if "alias" in b}
    io: list[Data] = []
    for entry in instance["fabric"]["io"]:
        key = f"{instance['name']}.{port_of[entry['alias']]}"
        channels = variable.get(key, [])
        if key in fixed or not channels:
            io.append(entry)
        io += [{"alias": entry["alias"], "name": channel} for channel in channels]
    instance["fabric"]["io"] = io

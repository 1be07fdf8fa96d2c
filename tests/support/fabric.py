"""FABRIC's own code from ``../shared/fabric`` (beside the checkout), unmodified: its parser of
``spec/subsystem.xml`` and the ``logicExprToCpp()`` of its master generator, and the rules of
its deployer's ``runXmls()`` as data (metamodel/fabric/configuration.toml)."""

from __future__ import annotations

import copy
import importlib.util
import re
import subprocess
import tomllib
import xml.etree.ElementTree as ElementTree
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
FABRIC = ROOT.parent / "shared" / "fabric"
CMAKE = FABRIC / "agent_orocos" / "rtt_subsystem" / "cmake"
EXAMPLES = FABRIC / "examples"
RULES = ROOT / "metamodel" / "fabric" / "configuration.toml"


def _require() -> None:
    if not (CMAKE / "parse_subsystem_xml.py").is_file():
        pytest.skip("FABRIC's sources (../shared/fabric) are not beside the checkout")


def parser() -> ModuleType:
    """FABRIC's parse_subsystem_xml module (it imports only xml.dom.minidom)."""
    _require()
    spec = importlib.util.spec_from_file_location("parse_subsystem_xml", CMAKE / "parse_subsystem_xml.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def logic_expr_to_cpp() -> Callable[[str, list[str]], str]:
    """``logicExprToCpp`` taken verbatim from create_master_cpp.py (the module itself needs ROS 1
    and Python 2, so only the function's source is executed)."""
    _require()
    source = (CMAKE / "create_master_cpp.py").read_text(encoding="utf-8")
    found = re.search(r"^def logicExprToCpp\(.*?(?=^def )", source, re.S | re.M)
    assert found is not None
    namespace: dict[str, Any] = {"copy": copy}
    exec(found.group(0), namespace)  # noqa: S102 - FABRIC's own code, read from its source
    function: Callable[[str, list[str]], str] = namespace["logicExprToCpp"]
    return function


def parse_spec(path: Path) -> Any:
    """FABRIC's SubsystemDefinition of a spec; raises what FABRIC raises."""
    return parser().parseSubsystemXml(path.read_text(encoding="utf-8"))


def conditions(sd: Any) -> list[tuple[str, str]]:
    """(where, condition text) of every condition of a parsed spec."""
    found = [(f"{b.name} stop_cond", b.stop_cond) for b in sd.behaviors]
    found += [(f"{b.name} err_cond", b.err_cond) for b in sd.behaviors]
    found += [(f"{s.name}->{name} init_cond", cond) for s in sd.states for name, cond in s.next_states]
    return found


def compile_conditions(sd: Any, work: Path) -> subprocess.CompletedProcess[str]:
    """g++ -fsyntax-only on every condition of a spec turned into C++ by logicExprToCpp, against
    a stub of the PredicateList struct FABRIC's master generator declares."""
    to_cpp = logic_expr_to_cpp()
    members = list(sd.predicates) + ["IN_ERROR", "CURRENT_BEHAVIOR_OK"]
    lines = ["struct PredicateList {"] + [f"    bool {m};" for m in members] + ["};", ""]
    for n, (where, text) in enumerate(conditions(sd)):
        lines += [f"// {where}: {text}", f"bool condition_{n}([[maybe_unused]] const PredicateList* p) {{",
                  f"    return {to_cpp(text, list(sd.predicates))};", "}", ""]
    source = work / "conditions.cpp"
    source.write_text("\n".join(lines), encoding="utf-8")
    return subprocess.run(["g++", "-std=c++17", "-fsyntax-only", "-Wall", "-Wextra", "-Werror", str(source)],
                          capture_output=True, text=True, timeout=120)


def rules() -> dict[str, Any]:
    return tomllib.loads(RULES.read_text(encoding="utf-8"))


def configuration_problems(path: Path, spec: Any) -> list[str]:
    """What SubsystemDeployer::runXmls() would refuse or ignore in a configuration, and the
    connection ends that name no component of it (or of the deployer) for the spec ``spec``."""
    table = rules()
    root = ElementTree.parse(path).getroot()
    problems: list[str] = []
    if root.tag != table["root"]:
        return [f"root <{root.tag}>, runXmls() wants <{table['root']}>"]
    elements = table["elements"]
    components: set[str] = set()
    for element in root:
        if element.tag not in elements:
            problems.append(f"<{element.tag}> is not read by runXmls()")
            continue
        rule = elements[element.tag]
        for attribute in rule["required"]:
            if not element.get(attribute):
                problems.append(f"<{element.tag}> without {attribute}")
        for attribute in element.attrib:
            if attribute not in rule["required"] + rule["optional"]:
                problems.append(f"<{element.tag}> attribute {attribute} is not read")
        for child in element:
            if child.tag not in rule.get("children", []):
                problems.append(f"<{element.tag}><{child.tag}> is not read")
        if element.tag == "component":
            components.add(element.get("name", ""))
        if element.tag == "connection":
            policy = element.find("conn_policy")
            if policy is not None:
                kind, size = policy.get("type", ""), policy.get("size")
                if kind not in table["conn_policy"]:
                    problems.append(f"conn_policy type {kind!r}")
                elif table["conn_policy"][kind] == "forbidden" and size is not None:
                    problems.append(f"conn_policy {kind} with a size")
                elif table["conn_policy"][kind] == "required" and not (size and size.isdigit() and int(size) > 0):
                    problems.append(f"conn_policy {kind} without a positive size")
    deployer = table["deployer"]
    inputs = {b.alias for b in spec.buffers_in}
    outputs = {b.alias for b in spec.buffers_out}
    ports = {f"{deployer['master_component']}.{a}_OUTPORT" for a in inputs}
    ports |= {f"{deployer['output_component']}.{a}_INPORT" for a in outputs}
    deployed = components | {f"{a}{deployer['split_suffix']}" for a in inputs}
    deployed |= {f"{a}{deployer['concate_suffix']}" for a in outputs}
    for connection in root.iter("connection"):
        for end in (connection.get("from", ""), connection.get("to", "")):
            component = end.partition(".")[0]
            if end not in ports and component not in deployed:
                problems.append(f"connection end {end} names no component")
    aliases = {b.get("alias") for b in root.iter("io_buffer")}
    if aliases - inputs - outputs:
        problems.append(f"io_buffer aliases not in the spec: {sorted(aliases - inputs - outputs)}")
    return problems

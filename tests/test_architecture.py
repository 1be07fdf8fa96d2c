"""The package keeps the structure docs/architecture.md describes: no import circles between
modules, imports that run down the layers of docs/layers.toml, conditions parsed only by the
lift, the stages after the lift reading the lifted model and never the XMI, and modules and
functions of a readable size."""

from __future__ import annotations

import ast

import pytest

from tests.support.import_graph import PACKAGE, Layers, Module, circles, edges, layers, modules, upward

MAX_MODULE_LINES = 450
MAX_FUNCTION_LINES = 80
MAX_UPWARD = 4
AFTER_THE_LIFT = ("check", "verify", "gen", "diff", "analysis", "report", "trace", "element_tree")


@pytest.fixture(scope="module")
def found() -> dict[str, Module]:
    return modules()


@pytest.fixture(scope="module")
def table() -> Layers:
    return layers()


def test_no_module_imports_itself_through_others(found: dict[str, Module]) -> None:
    assert circles(found) == []


def test_every_module_is_in_a_layer(found: dict[str, Module], table: Layers) -> None:
    for name in found:
        table.layer_of(name)  # raises for a module no layer names


def test_imports_run_down_the_layers(found: dict[str, Module], table: Layers) -> None:
    against = upward(found, table)
    assert set(against) <= table.exceptions, f"imports from a lower layer to a higher one: {against}"
    assert len(table.exceptions) <= MAX_UPWARD


def test_the_layer_check_sees_an_import_that_runs_up(found: dict[str, Module], table: Layers) -> None:
    model = found[f"{PACKAGE}.model.elements"]
    wrong = Module(model.name, model.path, model.lines, model.imports + ((f"{PACKAGE}.gen.generate", 1),),
                   model.functions)
    assert (model.name, f"{PACKAGE}.gen.generate") in upward({**found, model.name: wrong}, table)
    assert circles({**found, model.name: wrong})  # gen reads the model: a circle too


def test_the_stages_after_the_lift_do_not_read_the_xmi(found: dict[str, Module]) -> None:
    readers = {f"{PACKAGE}.read", f"{PACKAGE}.sysml2"}
    for source, target in sorted(edges(found)):
        stage = source.split(".")[1] if "." in source else ""
        if stage in AFTER_THE_LIFT:
            assert not any(target == r or target.startswith(r + ".") for r in readers), f"{source} imports {target}"


def test_conditions_are_parsed_by_the_lift_alone(found: dict[str, Module]) -> None:
    parsers = {"parse_condition", "parse_predicate", "parsed"}
    users = set()
    for module in found.values():
        tree = ast.parse(module.path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Call):
                called = node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", "")
                if called in parsers:
                    users.add(module.name)
    predicate_language = {m for m in users if m.startswith(f"{PACKAGE}.predicate.")}
    assert users - predicate_language == {f"{PACKAGE}.lift.conditions"}


def test_modules_and_functions_stay_readable(found: dict[str, Module]) -> None:
    long_modules = {m.name: m.lines for m in found.values() if m.lines > MAX_MODULE_LINES}
    long_functions = {f"{m.name}.{name}": lines for m in found.values() for name, lines in m.functions
                      if lines > MAX_FUNCTION_LINES}
    assert long_modules == {}
    assert long_functions == {}

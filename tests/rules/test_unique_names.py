"""S012: one name per element in every namespace, in every dialect.

For each kind of element, a sample with one name given twice is checked in the four dialects:

- Papyrus, Cameo and Enterprise Architect: the file the sample script writes
  (``scripts/make_two_arm.py``, ``scripts/make_sample.py``), the builder method that makes the
  element wrapped so that it makes a second one of the name right after the first (made under
  another name, so that the builder gives it ids of its own, then renamed), or, for a basic
  behaviour, gives a state's behaviour the name of another state's;
- SysML v2: the sample's text with the element's declaration written twice (or renamed).

Exactly one S012 error of that kind is reported, at the second element, naming the first's line;
D004 does not report the name as well. The samples as they are have no S012 finding, unnamed
transitions and links between the same ends are no repetition, and ``gen`` refuses a model with
a name given twice.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from lxml import etree

from earl_m2t import Diagnostic, check, load
from earl_m2t.convert import to_sysml
from tests.support import cameo_builder, ea_builder, papyrus_builder
from tests.test_sample_dialects_equal import SAMPLE_FILES

ROOT = Path(__file__).resolve().parents[2]
XMI_DIALECTS = ("papyrus", "cameo", "ea")
SUFFIXES = {"papyrus": "uml", "cameo": "cameo.xmi", "ea": "ea.xml"}
TWIN = "~twin"  # the name a second element is made under before it is renamed

Made = list[Any]  # the builder's elements that have the name, in the order they were made
Wrap = Callable[[Callable[..., Any], Made], Callable[..., Any]]


# ---- the XMI dialects: a sample script with one builder method wrapped -----------------------


@cache
def script(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name, ROOT / "scripts" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def twice(when: Callable[[Any, str], bool]) -> Wrap:
    """A method ``(owner, name, …)`` that makes, where ``when(owner, name)``, a second element
    of that name right after the first."""
    def wrap(make: Callable[..., Any], made: Made) -> Callable[..., Any]:
        def method(owner: Any, name: str, *args: Any, **kwargs: Any) -> Any:
            first = make(owner, name, *args, **kwargs)
            if when(owner, name):
                second = make(owner, name + TWIN, *args, **kwargs)
                second.name = name
                made.extend((first, second))
            return first
        return method
    return wrap


def named(target: str, owner: str = "") -> Wrap:
    """The element ``target`` (of the block, package … ``owner``) twice."""
    return twice(lambda made_in, name: name == target and owner in ("", made_in.name))


def transition_twice(source: str, target: str) -> Wrap:
    """``StateMachine.transition(source, target, …)``: the transition twice, both of its name."""
    def wrap(make: Callable[..., Any], made: Made) -> Callable[..., Any]:
        def method(fsm: Any, src: Any, dst: Any, guard: str | None = None, name: str | None = None,
                   *args: Any, **kwargs: Any) -> Any:
            first = make(fsm, src, dst, guard, name, *args, **kwargs)
            if (src.name, dst.name) == (source, target):
                second = make(fsm, src, dst, guard, TWIN, *args, **kwargs)
                second.name = first.name
                made.extend((first, second))
            return first
        return method
    return wrap


def behaviour_named_as(state: str, other: str) -> Wrap:
    """``State.do_activity``: the basic behaviour of ``state`` named as that of ``other`` (made first)."""
    def wrap(make: Callable[..., Any], made: Made) -> Callable[..., Any]:
        def method(owner: Any, name: str | None = None, *args: Any, **kwargs: Any) -> Any:
            if owner.name == state:
                name = f"{other}/bb"
            activity = make(owner, name, *args, **kwargs)
            if owner.name in (state, other):
                made.append(activity)
            return activity
        return method
    return wrap


@contextmanager
def wrapped(dialect: str, where: tuple[str, str], wrap: Wrap) -> Iterator[Made]:
    """The builder method ``where`` (class, method) of the dialect wrapped while the sample is built."""
    module = papyrus_builder if dialect == "papyrus" else cameo_builder  # EA writes cameo_builder's model
    cls = getattr(module, where[0])
    original = cls.__dict__[where[1]]
    made: Made = []
    setattr(cls, where[1], wrap(original, made))
    try:
        yield made
    finally:
        setattr(cls, where[1], original)


def xmi_id(dialect: str, element: Any) -> str:
    """The id the dialect's builder gives ``element``."""
    if dialect == "papyrus":
        return str(element.id)
    if dialect == "cameo":
        return cameo_builder.md_id(element.key)
    prefix = "EAPK_" if isinstance(element, cameo_builder.Package) else "EAID_"
    return prefix + ea_builder.ea_guid(element.key)


def element_of(data: bytes, element_id: str) -> etree._Element:
    """The model element with the xmi:id (not a tool's record of it in an ``xmi:Extension``)."""
    found = etree.fromstring(data).xpath(
        "//*[@*[local-name()='id' and namespace-uri()!=''] = $i][not(ancestor::*[local-name()='Extension'])]",
        i=element_id)
    assert len(found) == 1, f"{element_id}: {len(found)} elements"
    return found[0]


def own_line(element: etree._Element) -> int:
    return int(element.sourceline)


def formula_line(element: etree._Element) -> int:
    """Where an LTL property is: at its formula, the ``<body>`` of its specification (or the
    specification, whose ``body=`` it is)."""
    found = element.xpath("*[local-name()='specification']/*[local-name()='body'] | *[local-name()='specification']")
    return int(found[-1].sourceline if found else element.sourceline)


# ---- the SysML v2 dialect: a declaration written twice -------------------------------------------


def declaration_end(lines: list[str], start: int) -> int:
    """The index after the declaration that starts at ``lines[start]`` (up to its ``;`` or the
    brace that closes it)."""
    depth = 0
    for index in range(start, len(lines)):
        depth += lines[index].count("{") - lines[index].count("}")
        if depth <= 0 and lines[index].rstrip().endswith((";", "}")):
            return index + 1
    raise AssertionError(f"no end for the declaration at line {start + 1}")


def written_twice(text: str, start: str, occurrence: int = 0) -> tuple[str, int, int]:
    """The text with the declaration whose line starts with ``start`` written twice; the lines
    of the first and of the second."""
    lines = text.splitlines(keepends=True)
    starts = [n for n, line in enumerate(lines) if line.strip().startswith(start)]
    assert len(starts) > occurrence, start
    first = starts[occurrence]
    end = declaration_end(lines, first)
    return "".join(lines[:end] + lines[first:end] + lines[end:]), first + 1, end + 1


def declared_twice(start: str) -> Callable[[str], tuple[str, int, int]]:
    return lambda text: written_twice(text, start)


def renamed(text: str, declaration: str, new: str) -> tuple[str, int, int]:
    """The text with ``declaration`` given the name of ``new``, the declaration before it."""
    lines = text.splitlines(keepends=True)
    first = next(n for n, line in enumerate(lines) if new in line)
    second = next(n for n, line in enumerate(lines) if declaration in line)
    assert first < second
    lines[second] = lines[second].replace(declaration, new)
    return "".join(lines), first + 1, second + 1


# ---- the kinds -------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Twin:
    """A name given twice: the kind and path the finding names, the sample (two_arm or
    pick_and_place), how the XMI builders and the SysML v2 text give the name twice."""

    kind: str
    path: str
    sample: str
    builder: tuple[str, str]  # (class, method) of the builders that makes the element
    wrap: Wrap
    sysml: Callable[[str], tuple[str, int, int]]
    place: Callable[[etree._Element], int] = own_line  # the line a finding names, of the XMI element


SCRIPTS = {"two_arm": "make_two_arm", "pick_and_place": "make_sample"}

TWINS = {
    "configuration": Twin("configuration", "TwoArmCell.useB", "two_arm", ("Block", "configuration"),
                          named("useB"), declared_twice("metadata useB")),
    "ltl-property": Twin("LTL property", "armAOffInUseB", "two_arm", ("Block", "ltl_property"),
                         named("armAOffInUseB"), declared_twice("metadata armAOffInUseB"), formula_line),
    "datatype": Twin("dataType", "DataTypes::ManipulatorState", "two_arm", ("Package", "data_type"),
                     named("ManipulatorState"), declared_twice("attribute def ManipulatorState")),
    "field": Twin("field", "DataTypes::ManipulatorState.busy", "two_arm", ("DataType", "field"),
                  named("busy", "ManipulatorState"), declared_twice("attribute busy")),
    "input-buffer": Twin("input buffer", "manipA/a.cs.manipulatorCommand/ib", "two_arm", ("Block", "input_buffer"),
                         named("manipulatorCommand/ib"), declared_twice("port 'manipulatorCommand/ib'")),
    "output-buffer": Twin("output buffer", "manipA/a.cs.manipulatorState/ob", "two_arm", ("Block", "output_buffer"),
                          named("manipulatorState/ob"), declared_twice("port 'manipulatorState/ob'")),
    "memory": Twin("memory", "manipA/a.cs.lastSeq/m", "two_arm", ("Block", "memory"),
                   named("lastSeq/m"), declared_twice("attribute 'lastSeq/m'")),
    "pp": Twin("pp", "task/a.cs.handOver/pp", "two_arm", ("Block", "primitive_predicate"),
               named("handOver/pp"), declared_twice("calc def 'handOver/pp'")),
    "pf": Twin("pf", "task/a.cs.holdCommand/pf", "two_arm", ("Block", "partial_transition_function"),
               named("holdCommand/pf"), declared_twice("action def 'holdCommand/pf'")),
    "basic-behaviour": Twin("basic behaviour", "task/a.cs.withA/bb", "two_arm", ("State", "do_activity"),
                            behaviour_named_as("withB", "withA"),
                            lambda t: renamed(t, "do action 'withB/bb'", "do action 'withA/bb'")),
    "state": Twin("state", "task/a.cs.fsm.finished", "two_arm", ("StateMachine", "state"),
                  named("finished"), declared_twice("state finished")),
    "transition": Twin("transition", "task/a.cs.fsm.withB,finished/t", "two_arm", ("StateMachine", "transition"),
                       transition_twice("withB", "finished"), declared_twice("transition 'withB,finished/t'")),
    "agent": Twin("agent", "task/a", "two_arm", ("Block", "part"),
                  named("task/a"), declared_twice("part 'task/a'")),
    "subsystem": Twin("subsystem", "task/a.cs", "two_arm", ("Block", "part"),
                      named("cs", "TaskAgent"), declared_twice("part cs : TaskControl")),
    "system-link": Twin("link", "manipB/a,task/a", "two_arm", ("Block", "connector"),
                        named("manipB/a,task/a"), declared_twice("interface 'manipB/a,task/a'")),
    "agent-link": Twin("link", "grip/a.cs,fingerController/ve", "pick_and_place", ("Block", "connector"),
                       named("cs,fingerController/ve"), declared_twice("interface 'cs,fingerController/ve'")),
}


def _describe(findings: list[Diagnostic]) -> str:
    return "\n".join(f"  {d.code} {d.location.line}: {d.message}" for d in findings) or "  (none)"


def assert_reported_twice(findings: list[Diagnostic], twin: Twin, first: int, second: int) -> None:
    """One S012 error of the kind, at the second element, naming the first's line; no D004 for it."""
    found = [d for d in findings if d.code == "S012" and d.message.startswith(f"{twin.kind} ")]
    assert [(d.location.line, d.element, d.severity.value) for d in found] == [(second, twin.path, "error")], \
        _describe(findings)
    assert found[0].message.startswith(f"{twin.kind} {twin.path} is named twice (first at line {first}): "), \
        _describe(found)
    assert not [d for d in findings if d.code == "D004" and d.element == twin.path], _describe(findings)


@pytest.mark.parametrize("dialect", XMI_DIALECTS)
@pytest.mark.parametrize("kind", list(TWINS))
def test_a_name_given_twice_in_a_tool_file_is_an_error_at_the_second(kind: str, dialect: str,
                                                                       tmp_path: Path) -> None:
    twin = TWINS[kind]
    with wrapped(dialect, twin.builder, twin.wrap) as made:
        data = script(SCRIPTS[twin.sample]).build(dialect=dialect)
    assert len(made) == 2, f"the builder made {len(made)} elements of the name"
    first, second = (twin.place(element_of(data, xmi_id(dialect, element))) for element in made)
    path = tmp_path / f"{twin.sample}.{SUFFIXES[dialect]}"
    path.write_bytes(data)
    assert_reported_twice(check(path), twin, first, second)


@pytest.mark.parametrize("kind", list(TWINS))
def test_a_name_given_twice_in_sysml_text_is_an_error_at_the_second(kind: str, tmp_path: Path) -> None:
    twin = TWINS[kind]
    text, first, second = twin.sysml(SAMPLE_FILES[twin.sample]["sysml"].read_text(encoding="utf-8"))
    path = tmp_path / f"{twin.sample}.sysml"
    path.write_text(text, encoding="utf-8")
    assert_reported_twice(check(path), twin, first, second)


def test_a_name_given_three_times_is_reported_once_with_the_count(tmp_path: Path) -> None:
    text, first, second = written_twice(SAMPLE_FILES["two_arm"]["sysml"].read_text(encoding="utf-8"),
                                        "attribute 'lastSeq/m'")
    text, _, _ = written_twice(text, "attribute 'lastSeq/m'")
    path = tmp_path / "two_arm.sysml"
    path.write_text(text, encoding="utf-8")
    found = [d for d in check(path) if d.code == "S012"]
    assert [(d.location.line, d.message.partition(":")[0]) for d in found] == [
        (second, f"memory manipA/a.cs.lastSeq/m is named 3 times (first at line {first})")], _describe(found)


@pytest.mark.parametrize(("sample", "dialect"), [(sample, dialect) for sample, files in SAMPLE_FILES.items()
                                                 for dialect in files])
def test_the_samples_name_every_element_once(sample: str, dialect: str) -> None:
    assert [d for d in check(SAMPLE_FILES[sample][dialect]) if d.code == "S012"] == []


def test_the_ea_variants_name_every_element_once() -> None:
    variants = sorted((ROOT / "samples" / "pick_and_place" / "variants").glob("*.xml"))
    assert variants
    for variant in variants:
        assert [d for d in check(variant) if d.code == "S012"] == [], variant.name


# ---- what is no repetition ----------------------------------------------------------------------


def unnamed_transitions(source: str, target: str) -> Wrap:
    """``StateMachine.transition(source, target, …)`` twice, neither of them named."""
    def wrap(make: Callable[..., Any], made: Made) -> Callable[..., Any]:
        def method(fsm: Any, src: Any, dst: Any, *args: Any, **kwargs: Any) -> Any:
            first = make(fsm, src, dst, *args, **kwargs)
            if (src.name, dst.name) == (source, target):
                second = make(fsm, src, dst, *args, **{**kwargs, "name": TWIN})
                first.name = second.name = None
                made.extend((first, second))
            return first
        return method
    return wrap


@pytest.mark.parametrize("dialect", XMI_DIALECTS)
def test_unnamed_transitions_between_the_same_states_are_two_elements(dialect: str, tmp_path: Path) -> None:
    with wrapped(dialect, ("StateMachine", "transition"), unnamed_transitions("withB", "finished")) as made:
        data = script("make_two_arm").build(dialect=dialect)
    assert len(made) == 2
    path = tmp_path / f"two_arm.{SUFFIXES[dialect]}"
    path.write_bytes(data)
    assert b'name="withB,finished/t"' not in data and b"name='withB,finished/t'" not in data
    findings = check(path)
    assert [d for d in findings if d.code in ("S012", "D004")] == [], _describe(findings)


def test_unnamed_transitions_and_links_in_sysml_text_are_no_repetition(tmp_path: Path) -> None:
    text = SAMPLE_FILES["two_arm"]["sysml"].read_text(encoding="utf-8")
    text, _, _ = written_twice(text, "transition 'withB,finished/t'")
    text = text.replace("transition 'withB,finished/t'", "transition")
    assert "withB,finished/t" not in text
    pick = SAMPLE_FILES["pick_and_place"]["sysml"].read_text(encoding="utf-8")
    link = "connect cs.'fingerCommand/ob' to 'fingerController/ve'.'motorControllerCommand/ib';"
    assert pick.count(link) == 1
    pick = pick.replace("            interface 'cs,fingerController/ve' : InterSubsystemLink\n                " + link,
                        f"            {link}\n            {link}")
    assert pick.count(link) == 2
    for name, model in (("two_arm.sysml", text), ("pick_and_place.sysml", pick)):
        path = tmp_path / name
        path.write_text(model, encoding="utf-8")
        findings = check(path)
        assert [d for d in findings if d.code in ("S012", "D004")] == [], _describe(findings)


def test_converted_unnamed_transitions_between_the_same_states_stay_unnamed(tmp_path: Path) -> None:
    """``convert --to sysml`` writes an unnamed transition by the name it is called by, but not
    two of one name: then it leaves them unnamed, as the model does."""
    text = SAMPLE_FILES["two_arm"]["sysml"].read_text(encoding="utf-8")
    text, _, _ = written_twice(text, "transition 'withB,finished/t'")
    source = tmp_path / "two_arm.sysml"
    source.write_text(text.replace("transition 'withB,finished/t'", "transition"), encoding="utf-8")
    converted = to_sysml(load(source).model)
    assert converted.count("transition first withB if 'allHandedOver/pp'()") == 2, converted
    assert "transition 'withA,withB/t'" in converted
    path = tmp_path / "converted.sysml"
    path.write_text(converted, encoding="utf-8")
    findings = check(path)
    assert [d for d in findings if d.code in ("S012", "D004")] == [], _describe(findings)


def test_the_links_of_one_replicated_connector_are_one_element() -> None:
    """pick_and_place's manip/a joins its cs to each of six motorControllerK/ve with one
    connector of each direction: six links of a template name, at one place."""
    sample = SAMPLE_FILES["pick_and_place"]["papyrus"]
    manip = next(a for a in load(sample).model.agents if a.path == "manip/a")
    replicated = [link for link in manip.links if link.template == "cs,motorControllerK/ve"]
    assert len(replicated) == 6 and len({link.location for link in replicated}) == 1
    assert [d for d in check(sample) if d.code == "S012"] == []


# ---- two files ------------------------------------------------------------------------------------


def papyrus_file(body: str, name: str) -> str:
    return ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<xmi:XMI xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" '
            'xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML">\n'
            f'  <uml:Model xmi:id="_{name}" name="{name}">\n{body}  </uml:Model>\n</xmi:XMI>\n')


def test_a_name_given_again_in_another_file_names_that_file(tmp_path: Path) -> None:
    """The agents of an Agent Group are agents of the System: a group whose block is in
    another file may give an agent's name again."""
    main = tmp_path / "model.uml"
    main.write_text(papyrus_file("""\
    <packagedElement xmi:type="uml:Class" xmi:id="_system" name="Cell">
      <ownedAttribute xmi:id="_task" name="task/a" type="_agent" aggregation="composite"/>
      <ownedAttribute xmi:id="_helpers" name="helpers/ga" aggregation="composite">
        <type xmi:type="uml:Class" href="helpers.uml#_group"/>
      </ownedAttribute>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="_agent" name="TaskAgent">
      <ownedAttribute xmi:id="_cs" name="cs" type="_control" aggregation="composite"/>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="_control" name="TaskControl"/>
""", "Model"), encoding="utf-8")
    (tmp_path / "helpers.uml").write_text(papyrus_file("""\
    <packagedElement xmi:type="uml:Class" xmi:id="_group" name="Helpers">
      <ownedAttribute xmi:id="_again" name="task/a" aggregation="composite">
        <type xmi:type="uml:Class" href="model.uml#_agent"/>
      </ownedAttribute>
    </packagedElement>
""", "Helpers"), encoding="utf-8")
    found = [d for d in check(main) if d.code == "S012"]
    assert [(Path(d.location.file).name, d.location.line) for d in found] == [("helpers.uml", 5)], _describe(found)
    assert found[0].message.startswith(f"agent task/a is named twice (first at {main}:5): "), _describe(found)


# ---- gen --------------------------------------------------------------------------------------------


def test_gen_refuses_a_model_with_a_configuration_named_twice(tmp_path: Path) -> None:
    """The C++ switch of a state naming a configuration given twice took the other one's agents."""
    text = SAMPLE_FILES["two_arm"]["sysml"].read_text(encoding="utf-8")
    text, first, second = renamed(text, "metadata useB : Structure", "metadata useA : Structure")
    model = tmp_path / "two_arm.sysml"
    model.write_text(text, encoding="utf-8")
    out = tmp_path / "out"

    def gen(*options: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "earl_m2t", "gen", str(model), "--target", "cpp", "-o", str(out),
                               *options], cwd=ROOT, capture_output=True, text=True, timeout=300)

    result = gen()
    assert result.returncode == 1, result.stderr
    assert (f"{model}:{second}: S012 error: configuration TwoArmCell.useA is named twice (first at line {first})"
            in result.stderr), result.stderr
    assert "nothing generated" in result.stderr and not out.exists()
    # forced, the C++ view still does not pick one of the two
    forced = gen("--force")
    assert forced.returncode == 1, forced.stderr
    assert "TwoArmCell.useA: two configurations have this name (rule S012)" in forced.stderr, forced.stderr

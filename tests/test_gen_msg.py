"""``earl-m2t gen --target msg``: every generated message is read by the ROS 1 message parser
(genmsg, dependencies resolved, MD5 sums computed) and by rosbags, and both agree on every
MD5 sum; a misspelt type is caught; nested, array, optional and enumeration dataTypes map as
documented; regeneration is byte-identical; hostile names are refused, or mapped to valid,
distinct ROS names with --force; a message the model no longer produces is reported."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import rosbags.typesys as rosbags_typesys  # the second parser of the messages (test extra rosbags)
from genmsg import InvalidMsgSpec, MsgContext, MsgNotFound
from genmsg.gentools import compute_md5
from genmsg.msg_loader import load_depends, load_msg_by_type

from earl_m2t import check
from earl_m2t.api import load
from earl_m2t.gen import GenError, generate, render
from earl_m2t.gen.targets.msg import msg_settings
from earl_m2t.gen.views.msg import (
    CONSTANT_NAME,
    FIELD_NAME,
    MESSAGE_NAME,
    constant_name,
    field_name,
    message_name,
    name_problems,
    package_name,
)

ROOT = Path(__file__).resolve().parents[1]

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
PACKAGE = "pick_and_place_msgs"
SAMPLE_MESSAGES = ["EncoderReading", "GripperCommand", "GripperStatus", "JointPosition", "ManipulatorCommand",
                   "ManipulatorState", "MotorControllerCommand", "MotorControllerState", "MotorCurrent",
                   "OperPosition", "Quaternion", "Vector3"]
ROS_BUILTINS = {"bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64",
                "float32", "float64", "string", "time", "duration"}


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)


def model_with(tmp_path: Path, replacements: dict[str, str]) -> Path:
    text = SAMPLE.read_text(encoding="utf-8")
    for old, new in replacements.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / "model.uml"
    path.write_text(text, encoding="utf-8")
    shutil.copy(SAMPLE.parent / "EARL.profile.uml", tmp_path / "EARL.profile.uml")
    return path


def packages(out: Path) -> dict[str, Path]:
    """package name -> its msg folder, for every package folder gen wrote."""
    return {d.parent.name: d for d in sorted(out.glob("*/msg")) if d.is_dir()}


def parse_with_genmsg(out: Path) -> dict[str, tuple[object, str]]:
    """Every .msg under out/*/msg loaded by genmsg with its dependencies, and its MD5 sum
    (which needs every type it uses, recursively). Raises what genmsg raises."""
    search = {name: [str(folder)] for name, folder in packages(out).items()}
    uses_std_msgs = any("std_msgs/" in f.read_text(encoding="utf-8") or re.search(r"^Header ", f.read_text(
        encoding="utf-8"), re.M) for folder in search.values() for f in Path(folder[0]).glob("*.msg"))
    assert not uses_std_msgs, "a generated message uses std_msgs: give genmsg a std_msgs folder"
    context = MsgContext.create_default()
    found: dict[str, tuple[object, str]] = {}
    for package, folders in search.items():
        for path in sorted(Path(folders[0]).glob("*.msg")):
            full = f"{package}/{path.stem}"
            spec = load_msg_by_type(context, full, search)
            load_depends(context, spec, search)
            found[full] = (spec, compute_md5(context, spec))
    return found


def parse_with_rosbags(out: Path) -> dict[str, str]:
    """type name -> MD5 sum rosbags computes after registering every generated message."""
    store = rosbags_typesys.get_typestore(rosbags_typesys.Stores.EMPTY)
    types = {}
    for package, folder in packages(out).items():
        for path in sorted(folder.glob("*.msg")):
            types.update(rosbags_typesys.get_types_from_msg(path.read_text(encoding="utf-8"),
                                                            f"{package}/msg/{path.stem}"))
    store.register(types)
    return {name.replace("/msg/", "/"): store.generate_msgdef(name, ros_version=1)[1] for name in types}


def check_with_both_parsers(out: Path) -> dict[str, object]:
    """Both parsers read every file and agree on every MD5 sum; returns genmsg's specs."""
    by_genmsg = parse_with_genmsg(out)
    by_rosbags = parse_with_rosbags(out)
    assert set(by_genmsg) == set(by_rosbags)
    assert {k: md5 for k, (_, md5) in by_genmsg.items()} == by_rosbags
    return {k: spec for k, (spec, _) in by_genmsg.items()}


def fields(spec: object) -> list[tuple[str, str]]:
    return list(zip(spec.types, spec.names))  # type: ignore[attr-defined]


@pytest.fixture(scope="module")
def sample_out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("gen_msg") / "out"
    result = earl("gen", str(SAMPLE), "--target", "msg", "-o", str(out))
    assert result.returncode == 0, result.stderr
    return out


# ---------------------------------------------------------------- the sample, parsed


def test_the_sample_gives_one_message_per_used_datatype_in_a_ros_package(sample_out: Path) -> None:
    files = sorted(p.relative_to(sample_out).as_posix() for p in sample_out.rglob("*") if p.is_file())
    assert files == [".earl-trace.json"] + [f"{PACKAGE}/msg/{name}.msg" for name in SAMPLE_MESSAGES]  # + source map
    for path in sample_out.rglob("*.msg"):
        assert path.read_bytes().startswith(b"# Generated by earl-m2t from model PickAndPlace: dataType ")
        assert path.read_bytes().isascii()


def test_every_generated_message_is_read_by_genmsg_and_rosbags_with_the_same_md5(sample_out: Path) -> None:
    specs = check_with_both_parsers(sample_out)
    assert sorted(specs) == [f"{PACKAGE}/{name}" for name in SAMPLE_MESSAGES]


def test_nested_fixed_array_and_optional_fields_map_as_documented(sample_out: Path) -> None:
    specs = check_with_both_parsers(sample_out)
    assert fields(specs[f"{PACKAGE}/JointPosition"]) == [("float64[6]", "q")]
    assert fields(specs[f"{PACKAGE}/ManipulatorCommand"]) == [
        (f"{PACKAGE}/JointPosition[]", "joint_pos_setpoint"),       # [0..1]: a variable array
        (f"{PACKAGE}/OperPosition[]", "operational_pos_setpoint"),
        ("bool", "emergency_stop_command")]
    assert fields(specs[f"{PACKAGE}/OperPosition"]) == [(f"{PACKAGE}/Vector3", "position"),
                                                        (f"{PACKAGE}/Quaternion", "orientation")]
    assert fields(specs[f"{PACKAGE}/ManipulatorState"])[:2] == [(f"{PACKAGE}/JointPosition", "current_joint_pos"),
                                                                (f"{PACKAGE}/OperPosition", "current_operational_pos")]
    text = (sample_out / PACKAGE / "msg" / "ManipulatorCommand.msg").read_text(encoding="utf-8")
    assert "JointPosition[] joint_pos_setpoint  # jointPosSetpoint: JointPosition[0..1], optional" in text


# ---------------------------------------------------------------- the check can fail


@pytest.mark.parametrize(("old", "new", "error"), [
    ("JointPosition[] joint_pos_setpoint", "JointPositon[] joint_pos_setpoint", MsgNotFound),  # misspelt message
    ("bool emergency_stop_command", "boool emergency_stop_command", MsgNotFound),              # misspelt builtin
    ("bool emergency_stop_command", "bool emergency stop_command", InvalidMsgSpec),            # not a declaration
])
def test_a_misspelt_type_in_a_generated_file_is_caught_by_genmsg(sample_out: Path, tmp_path: Path, old: str,
                                                                  new: str, error: type[Exception]) -> None:
    out = tmp_path / "out"
    shutil.copytree(sample_out, out)
    path = out / PACKAGE / "msg" / "ManipulatorCommand.msg"
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new), encoding="utf-8")
    with pytest.raises(error):
        parse_with_genmsg(out)


# ---------------------------------------------------------------- enumerations, arrays, primitives

EXTENDED = {
    'name="DataTypes">': '''name="DataTypes">
      <packagedElement xmi:type="uml:Enumeration" xmi:id="_tGripMode" name="GripMode">
        <ownedLiteral xmi:type="uml:EnumerationLiteral" xmi:id="_tOpen" name="open"/>
        <ownedLiteral xmi:type="uml:EnumerationLiteral" xmi:id="_tClose" name="close"/>
        <ownedLiteral xmi:type="uml:EnumerationLiteral" xmi:id="_tHold" name="holdPosition"/>
      </packagedElement>
      <packagedElement xmi:type="uml:PrimitiveType" xmi:id="_tUN" name="UnlimitedNatural"/>''',
    'name="GripperCommand">': '''name="GripperCommand">
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA1" name="mode" type="_tGripMode"/>
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA2" name="modeHistory" type="_tGripMode">
          <lowerValue xmi:type="uml:LiteralInteger" xmi:id="_tA2l"/>
          <upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="_tA2u" value="*"/>
        </ownedAttribute>
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA3" name="label">
          <type xmi:type="uml:PrimitiveType" href="pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#String"/>
        </ownedAttribute>
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA4" name="tags">
          <type xmi:type="uml:PrimitiveType" href="pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#String"/>
          <lowerValue xmi:type="uml:LiteralInteger" xmi:id="_tA4l"/>
          <upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="_tA4u" value="*"/>
        </ownedAttribute>
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA5" name="graspCount" type="_tUN"/>
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA6" name="approachPath" type="_Oe8w7_5UvWYPYeiAv5XvdA">
          <lowerValue xmi:type="uml:LiteralInteger" xmi:id="_tA6l" value="1"/>
          <upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="_tA6u" value="5"/>
        </ownedAttribute>
        <ownedAttribute xmi:type="uml:Property" xmi:id="_tA7" name="fingerPoses" type="_d_6U-VwfwB0JhfDmM7DN6w">
          <lowerValue xmi:type="uml:LiteralInteger" xmi:id="_tA7l" value="2"/>
          <upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="_tA7u" value="2"/>
        </ownedAttribute>''',
}


def test_enumerations_strings_unbounded_and_bounded_arrays_map_as_documented(tmp_path: Path) -> None:
    model = load(model_with(tmp_path, EXTENDED)).model
    out = tmp_path / "out"
    generate(model, out, "msg")
    specs = check_with_both_parsers(out)
    assert f"{PACKAGE}/GripMode" in specs
    grip_mode = specs[f"{PACKAGE}/GripMode"]
    assert [(c.type, c.name, c.val) for c in grip_mode.constants] == [  # type: ignore[attr-defined]
        ("uint8", "OPEN", 0), ("uint8", "CLOSE", 1), ("uint8", "HOLD_POSITION", 2)]
    assert fields(grip_mode) == [("uint8", "value")]
    assert fields(specs[f"{PACKAGE}/GripperCommand"]) == [
        ("uint8", "mode"), ("uint8[]", "mode_history"), ("string", "label"), ("string[]", "tags"),
        ("uint64", "grasp_count"), (f"{PACKAGE}/JointPosition[]", "approach_path"),
        (f"{PACKAGE}/OperPosition[2]", "finger_poses"),
        ("float64", "desired_finger_pos"), ("bool", "emergency_stop_command")]
    text = (out / PACKAGE / "msg" / "GripperCommand.msg").read_text(encoding="utf-8")
    assert "uint8 mode  # mode: GripMode, one of the constants of GripMode" in text
    assert "approachPath: JointPosition[1..5], 1 to 5 elements" in text


# ---------------------------------------------------------------- determinism


def test_regenerating_gives_identical_bytes_and_rewrites_nothing(tmp_path: Path) -> None:
    model = load(SAMPLE).model
    first = generate(model, tmp_path / "a", "msg")
    assert len(first.write.written) == len(SAMPLE_MESSAGES) + 1 and first.orphans == ()  # + the source map
    before = {p: (p.read_bytes(), p.stat().st_ino, p.stat().st_mtime_ns) for p in (tmp_path / "a").rglob("*.msg")}
    second = generate(model, tmp_path / "a", "msg")
    assert second.write.written == () and len(second.write.unchanged) == len(SAMPLE_MESSAGES) + 1
    assert {p: (p.read_bytes(), p.stat().st_ino, p.stat().st_mtime_ns)
            for p in (tmp_path / "a").rglob("*.msg")} == before
    assert render(load(SAMPLE).model, "msg").generated == render(model, "msg").generated


def test_a_message_the_model_no_longer_produces_is_reported_and_kept(tmp_path: Path) -> None:
    out = tmp_path / "out"
    generate(load(SAMPLE).model, out, "msg")
    renamed = load(model_with(tmp_path, {'name="Vector3"': 'name="Position3"'})).model
    report = generate(renamed, out, "msg")
    assert report.orphans == (f"{PACKAGE}/msg/Vector3.msg",)
    assert (out / PACKAGE / "msg" / "Vector3.msg").is_file()
    assert any(line.startswith("orphaned ") and line.endswith("(kept; nothing in the model generates it any more)")
               for line in report.lines())


# ---------------------------------------------------------------- names


@pytest.mark.parametrize(("name", "message", "field", "constant"), [
    ("jointPosSetpoint", "JointPosSetpoint", "joint_pos_setpoint", "JOINT_POS_SETPOINT"),
    ("motionFinished/m", "MotionFinishedM", "motion_finished_m", "MOTION_FINISHED_M"),
    ("XMLParser2Go", "XMLParser2Go", "xml_parser2_go", "XML_PARSER2_GO"),
    ("motor  state__x_", "MotorStateX", "motor_state_x", "MOTOR_STATE_X"),
    ("Vektor größe", "VektorGrou00dfe", "vektor_grou00dfe", "VEKTOR_GROU00DFE"),
    ("9lives", "M9lives", "n9lives", "N9LIVES"),
    ("../../escape", "Escape", "escape", "ESCAPE"),
    ("日本", "U65e5u672c", "u65e5u672c", "U65E5U672C"),
    ("", "Unnamed", "unnamed", "UNNAMED"),
])
def test_names_map_deterministically_to_valid_ros_names(name: str, message: str, field: str,
                                                         constant: str) -> None:
    assert (message_name(name), field_name(name), constant_name(name)) == (message, field, constant)
    assert MESSAGE_NAME.match(message) and FIELD_NAME.match(field) and CONSTANT_NAME.match(constant)
    assert package_name("PickAndPlace", "_msgs") == PACKAGE


HOSTILE = {
    'name="PickAndPlace"': 'name="Pick-and-Place"',             # not an identifier: package pick_and_place_msgs
    'name="Quaternion"': 'name="Header"',                      # ROS 1 would read std_msgs/Header
    'name="Vector3"': 'name="Vektor größe"',                   # non-ASCII letters and a space
    'name="EncoderReading"': 'name="motor current"',           # collides with MotorCurrent
    'name="operationalPosSetpoint"': 'name="joint_pos_setpoint"',  # collides with jointPosSetpoint
    'name="w"': 'name="from"',                                 # a Python keyword
    'name="x"': 'name="float64"',                              # a ROS builtin type
}


def test_hostile_names_are_refused_by_the_check_and_by_the_view(tmp_path: Path) -> None:
    model = model_with(tmp_path, HOSTILE)
    result = earl("gen", str(model), "--target", "msg", "-o", str(tmp_path / "out"))
    assert result.returncode == 1
    assert "D003" in result.stderr and "nothing generated" in result.stderr
    assert not (tmp_path / "out").exists()
    with pytest.raises(GenError) as refused:  # the API, without the check: the view refuses by itself
        render(load(model).model, "msg")
    message = str(refused.value)
    assert "--force" in message and "\n" not in message
    assert ("D004 field DataTypes::ManipulatorCommand.joint_pos_setpoint: 'joint_pos_setpoint' and "
            "'jointPosSetpoint' both map to the ROS field name 'joint_pos_setpoint' (--force: 'joint_pos_setpoint_2')"
            in message)
    assert ("D004 dataType DataTypes::motor current: 'motor current' and 'MotorCurrent' both map to the ROS "
            "message name 'MotorCurrent' (--force: 'MotorCurrent2')" in message)
    assert "D003 dataType DataTypes::Header" in message and "D003 field DataTypes::Header.from" in message


def test_hostile_names_forced_give_valid_distinct_names_that_both_parsers_read(tmp_path: Path) -> None:
    model = model_with(tmp_path, HOSTILE)
    out = tmp_path / "out"
    result = earl("gen", str(model), "--target", "msg", "-o", str(out), "--force")
    assert result.returncode == 0, result.stderr
    assert list(packages(out)) == [PACKAGE]
    names = sorted(p.stem for p in (out / PACKAGE / "msg").glob("*.msg"))
    assert "HeaderMsg" in names and "VektorGrou00dfe" in names and {"MotorCurrent", "MotorCurrent2"} <= set(names)
    assert "Header" not in names and len({n.lower() for n in names}) == len(names)
    specs = check_with_both_parsers(out)
    for full, spec in specs.items():
        assert MESSAGE_NAME.match(full.split("/")[1])
        field_names = list(spec.names)  # type: ignore[attr-defined]
        assert all(FIELD_NAME.match(n) and n not in ROS_BUILTINS for n in field_names), field_names
        assert len(set(field_names)) == len(field_names)
    assert fields(specs[f"{PACKAGE}/ManipulatorCommand"])[:2] == [
        (f"{PACKAGE}/JointPosition[]", "joint_pos_setpoint"), (f"{PACKAGE}/OperPosition[]", "joint_pos_setpoint_2")]
    assert fields(specs[f"{PACKAGE}/VektorGrou00dfe"]) == [("float64", "float64_field"), ("float64", "y"),
                                                           ("float64", "z")]
    assert fields(specs[f"{PACKAGE}/HeaderMsg"]) == [("float64", "x"), ("float64", "y"), ("float64", "z"),
                                                     ("float64", "from_field")]
    assert fields(specs[f"{PACKAGE}/OperPosition"]) == [(f"{PACKAGE}/VektorGrou00dfe", "position"),
                                                        (f"{PACKAGE}/HeaderMsg", "orientation")]


def test_check_reports_every_name_the_view_refuses_at_its_element(tmp_path: Path) -> None:
    """D003 and D004 ask the view itself which names it refuses, so check and gen cannot drift."""
    model = model_with(tmp_path, HOSTILE)
    problems = name_problems(load(model).model, msg_settings())
    assert {p.rule for p in problems} == {"D003", "D004"}
    findings = [d for d in check(model) if d.code in ("D003", "D004")]
    for problem in problems:
        assert any(d.code == problem.rule and d.location.line == problem.location.line for d in findings), \
            f"check does not report {problem}"


# A field copied with its xmi:id onto the same line: one name twice at one place (R002 warns of
# the id); check passed it, gen --target msg refused 'position' and 'position'.
COPIED_FIELD = ('<ownedAttribute xmi:type="uml:Property" xmi:id="_FgyCnOO_1T_EU1uO-WuWiQ" name="position">'
                '<type xmi:type="uml:PrimitiveType" '
                'href="pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#Real"/></ownedAttribute>')


def test_a_field_copied_with_its_id_onto_one_line_is_refused_by_check(tmp_path: Path) -> None:
    text = SAMPLE.read_text(encoding="utf-8")
    field = text.index('<ownedAttribute xmi:type="uml:Property" xmi:id="_FgyCnOO_1T_EU1uO-WuWiQ"')
    end = text.index("</ownedAttribute>", field) + len("</ownedAttribute>")
    model = tmp_path / "model.uml"
    model.write_text(text[:field] + COPIED_FIELD * 2 + text[end:], encoding="utf-8")
    shutil.copy(SAMPLE.parent / "EARL.profile.uml", tmp_path / "EARL.profile.uml")
    errors = [d for d in check(model) if d.severity == "error"]
    assert [(d.code, d.element) for d in errors] == [("S012", "DataTypes::EncoderReading.position")], errors
    assert "field DataTypes::EncoderReading.position is named twice (first at line " in errors[0].message
    result = earl("gen", str(model), "--target", "msg", "-o", str(tmp_path / "out"))
    assert result.returncode == 1 and "S012" in result.stderr and "nothing generated" in result.stderr


@pytest.mark.parametrize("name", ["éééééééééé", "éééééééééé/a", "Straße"])
def test_a_model_name_that_cannot_name_the_package_is_refused_by_check(tmp_path: Path, name: str) -> None:
    text = (ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml").read_text(encoding="utf-8")
    model = tmp_path / "model.sysml"
    model.write_text(text.replace("package PickAndPlace {", f"package '{name}' {{", 1), encoding="utf-8")
    errors = [d for d in check(model) if d.severity == "error"]
    assert [(d.code, d.element) for d in errors] == [("D003", "model")], errors
    assert f"model '{name}': cannot become a ROS package name" in errors[0].message
    assert errors[0].location.line > 0
    forced = earl("gen", str(model), "--target", "msg", "--force", "-o", str(tmp_path / "out"))
    assert forced.returncode == 0, forced.stderr


def test_the_target_is_registered_for_the_api_and_the_cli() -> None:
    with pytest.raises(GenError, match="one of cpp, msg"):
        render(load(SAMPLE).model, "rust")
    assert "msg" in earl("gen", "--help").stdout

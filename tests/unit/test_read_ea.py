"""Reading Enterprise Architect XMI: the "XMI 2.1" export and the export with EA 2013 namespaces."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from earl_m2t.api import load
from earl_m2t.lift import lift
from earl_m2t.lift.replication import multiplicity
from earl_m2t.read.connector_ends import resolve_end
from earl_m2t.read.loader import load_raw_model
from earl_m2t.read.xmi import ExternalRef, RawModel

ROOT = Path(__file__).resolve().parents[2]

# EA "XMI 2.1": windows-1252, the exported package inside <uml:Model name="EA_Model">, stereotype
# applications without ids inside that model (lower-case SysML names, spaces written as "_" with
# the real name in __EAStereoName, base_Attribute), types as <type xmi:idref>, EAJava_ primitives,
# ports as ownedPort, connector ends on <qualifier> copies of the ports under the parts (copies of
# copies for nested parts), no classifierBehavior, guards inline with a body= attribute, triggers
# as nestedClassifiers, multiplicities on every attribute (-1 for *, LiteralInteger uppers), and an
# xmi:Extension that repeats model ids.
EA21 = """<?xml version="1.0" encoding="windows-1252"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1" \
xmlns:thecustomprofile="http://www.sparxsystems.com/profiles/thecustomprofile/1.0" \
xmlns:EARL="http://www.sparxsystems.com/profiles/EARL/1.0" xmlns:SysML1.4="http://www.sparxsystems.com/profiles/SysML1.4/1.4">
	<xmi:Documentation exporter="Enterprise Architect" exporterVersion="6.5"/>
	<uml:Model xmi:type="uml:Model" name="EA_Model" visibility="public">
		<packagedElement xmi:type="uml:Package" xmi:id="EAPK_CELL" name="Cell" visibility="public">
			<packagedElement xmi:type="uml:DataType" xmi:id="EAID_CMD" name="Command" visibility="public">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_SPEED" name="speed" visibility="public">
					<type xmi:idref="EAJava_double"/>
					<lowerValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000001_SPEED" value="0"/>
					<upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="EAID_LI000002_SPEED" value="-1"/>
				</ownedAttribute>
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_AXES" name="axes" visibility="public">
					<type xmi:idref="EAJava_int"/>
					<lowerValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000003_AXES" value="3"/>
					<upperValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000004_AXES" value="3"/>
				</ownedAttribute>
			</packagedElement>
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_CS" name="Control" visibility="public">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_HIST" name="history/m" visibility="public">
					<type xmi:idref="EAID_CMD"/>
					<lowerValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000005_HIST" value="0"/>
					<upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="EAID_LI000006_HIST" value="-1"/>
				</ownedAttribute>
				<ownedBehavior xmi:type="uml:StateMachine" xmi:id="EAID_SM" name="fsm" visibility="public">
					<region xmi:type="uml:Region" xmi:id="EAID_SR000001_SM" name="EA_Region1" visibility="public">
						<subvertex xmi:type="uml:Pseudostate" xmi:id="EAID_START" name="Start" kind="initial">
							<outgoing xmi:idref="EAID_T0"/>
						</subvertex>
						<subvertex xmi:type="uml:State" xmi:id="EAID_IDLE" name="idle" isSubmachineState="false">
							<incoming xmi:idref="EAID_T0"/>
							<outgoing xmi:idref="EAID_T1"/>
						</subvertex>
						<subvertex xmi:type="uml:State" xmi:id="EAID_RUN" name="run" isSubmachineState="false">
							<incoming xmi:idref="EAID_T1"/>
						</subvertex>
						<transition xmi:type="uml:Transition" xmi:id="EAID_T0" kind="local" source="EAID_START" target="EAID_IDLE"/>
						<transition xmi:type="uml:Transition" xmi:id="EAID_T1" name="idle,run/t" kind="local" source="EAID_IDLE" target="EAID_RUN">
							<trigger xmi:idref="EAID_TRIG"/>
							<guard xmi:type="uml:Constraint" xmi:id="EAID_CO000000_T1">
								<specification xmi:type="uml:OpaqueExpression" xmi:id="EAID_OE000000_T1" body="\u00acstop/pp"/>
							</guard>
							<effect xmi:type="uml:OpaqueBehavior" xmi:id="EAID_OB000000_T1" body="count := 0"/>
						</transition>
					</region>
				</ownedBehavior>
				<ownedBehavior xmi:type="uml:StateMachine" xmi:id="EAID_SM2" name="spare" visibility="public"/>
				<ownedBehavior xmi:type="uml:OpaqueBehavior" xmi:id="EAID_STOP" name="stop/pp" visibility="public" body="FALSE"/>
				<nestedClassifier xmi:type="uml:Trigger" xmi:id="EAID_TRIG" name="go">
					<event xmi:type="uml:Event" xmi:id="EAID_EX000000_TRIG"/>
				</nestedClassifier>
				<ownedPort xmi:type="uml:Port" xmi:id="EAID_CS_OUT" name="cmd/ob" visibility="public" aggregation="composite" isService="true">
					<type xmi:idref="EAID_CMD"/>
				</ownedPort>
				<ownedPort xmi:type="uml:Port" xmi:id="EAID_CS_IN" name="cmd/ib" visibility="public" aggregation="composite" isService="true">
					<type xmi:idref="EAID_CMD"/>
				</ownedPort>
			</packagedElement>
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_DRIVE" name="Drive" visibility="public">
				<ownedPort xmi:type="uml:Port" xmi:id="EAID_DRIVE_IN" name="cmd/ib" visibility="public" aggregation="composite" isService="true">
					<type xmi:idref="EAID_CMD"/>
				</ownedPort>
			</packagedElement>
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_AGENT" name="Sender" visibility="public">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_P_CS" name="cs" visibility="public" aggregation="composite">
					<type xmi:idref="EAID_CS"/>
					<qualifier xmi:type="uml:Port" xmi:id="EAID_Q_CS_OUT" name="cmd/ob" aggregation="composite" isService="true">
						<type xmi:idref="EAID_CMD"/>
					</qualifier>
				</ownedAttribute>
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_P_DRIVE" name="driveK/ve" visibility="public" aggregation="composite">
					<type xmi:idref="EAID_DRIVE"/>
					<lowerValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000007_DRIVE" value="2"/>
					<upperValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000008_DRIVE" value="2"/>
					<qualifier xmi:type="uml:Port" xmi:id="EAID_Q_DRIVE_IN" name="cmd/ib" aggregation="composite" isService="true">
						<type xmi:idref="EAID_CMD"/>
					</qualifier>
				</ownedAttribute>
				<ownedConnector xmi:type="uml:Connector" xmi:id="EAID_K1" name="cs,driveK/ve" visibility="public">
					<end xmi:type="uml:ConnectorEnd" xmi:id="EAID_SC000000_K1" role="EAID_Q_CS_OUT"/>
					<end xmi:type="uml:ConnectorEnd" xmi:id="EAID_DS000000_K1" role="EAID_Q_DRIVE_IN"/>
				</ownedConnector>
			</packagedElement>
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_SYS" name="Ger\u00e4tezelle" visibility="public">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_P_A" name="a/a" visibility="public" aggregation="composite">
					<type xmi:idref="EAID_AGENT"/>
					<qualifier xmi:type="uml:Property" xmi:id="EAID_Q_A_CS" name="cs" aggregation="composite">
						<type xmi:idref="EAID_CS"/>
						<qualifier xmi:type="uml:Port" xmi:id="EAID_Q_A_OUT" name="cmd/ob" aggregation="composite" isService="true">
							<type xmi:idref="EAID_CMD"/>
						</qualifier>
					</qualifier>
				</ownedAttribute>
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_P_B" name="b/a" visibility="public" aggregation="composite">
					<type xmi:idref="EAID_AGENT"/>
					<qualifier xmi:type="uml:Property" xmi:id="EAID_Q_B_CS" name="cs" aggregation="composite">
						<type xmi:idref="EAID_CS"/>
						<qualifier xmi:type="uml:Port" xmi:id="EAID_Q_B_IN" name="cmd/ib" aggregation="composite" isService="true">
							<type xmi:idref="EAID_CMD"/>
						</qualifier>
					</qualifier>
				</ownedAttribute>
				<ownedConnector xmi:type="uml:Connector" xmi:id="EAID_K2" name="a/a,b/a" visibility="public">
					<end xmi:type="uml:ConnectorEnd" xmi:id="EAID_SC000000_K2" role="EAID_Q_A_OUT"/>
					<end xmi:type="uml:ConnectorEnd" xmi:id="EAID_DS000000_K2" role="EAID_Q_B_IN"/>
				</ownedConnector>
			</packagedElement>
		</packagedElement>
		<SysML1.4:block base_Class="EAID_SYS"/>
		<EARL:System base_Class="EAID_SYS"/>
		<SysML1.4:block base_Class="EAID_AGENT"/>
		<EARL:Agent base_Class="EAID_AGENT" declaredType="CE"/>
		<SysML1.4:block base_Class="EAID_CS"/>
		<EARL:Control_Subsystem base_Class="EAID_CS" __EAStereoName="Control Subsystem"/>
		<SysML1.4:block base_Class="EAID_DRIVE"/>
		<EARL:Virtual_Effector base_Class="EAID_DRIVE" __EAStereoName="Virtual Effector"/>
		<EARL:Internal_Memory base_Attribute="EAID_HIST" __EAStereoName="Internal Memory"/>
		<EARL:Output_Buffer base_Port="EAID_CS_OUT" __EAStereoName="Output Buffer"/>
		<EARL:Input_Buffer base_Port="EAID_CS_IN" __EAStereoName="Input Buffer"/>
		<EARL:Input_Buffer base_Port="EAID_DRIVE_IN" __EAStereoName="Input Buffer"/>
		<EARL:Output_Buffer base_Port="EAID_Q_CS_OUT" __EAStereoName="Output Buffer"/>
		<EARL:Fsm_Transition base_Transition="EAID_T1" __EAStereoName="Fsm Transition" priority="2"/>
		<EARL:Primitive_Predicate base_Behavior="EAID_STOP" __EAStereoName="Primitive Predicate"/>
		<thecustomprofile:note base_Attribute="EAID_SPEED"/>
	</uml:Model>
	<xmi:Extension extender="Enterprise Architect" extenderID="6.5">
		<elements>
			<element xmi:idref="EAID_AGENT" xmi:type="uml:Class" name="Sender" scope="public">
				<links><Aggregation xmi:id="EAID_K1" start="EAID_P_CS" end="EAID_P_DRIVE"/></links>
			</element>
			<element xmi:idref="EAID_P_CS" xmi:type="uml:Part" name="cs" scope="public"/>
			<element xmi:idref="EAID_IDLE" xmi:type="uml:StateNode" name="idle" scope="public">
				<links><StateFlow xmi:id="EAID_T1" start="EAID_IDLE" end="EAID_RUN"/></links>
			</element>
		</elements>
		<primitivetypes>
			<packagedElement xmi:type="uml:Package" xmi:id="EAPrimitiveTypesPackage" name="EA_PrimitiveTypes_Package">
				<packagedElement xmi:type="uml:PrimitiveType" xmi:id="EAJava_double" name="double"/>
			</packagedElement>
		</primitivetypes>
	</xmi:Extension>
</xmi:XMI>
"""

# EA with the EA 2013 namespaces (UML/XMI 20131001, SysML 1.5): applications at the root, after
# the xmi:Extension; the initial pseudostate without kind; types as <type xmi:idref>.
EA2013 = """<?xml version="1.0" encoding="windows-1252"?>
<xmi:XMI xmlns:uml="http://www.omg.org/spec/UML/20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" \
xmlns:umldi="http://www.omg.org/spec/UML/20131001/UMLDI" xmlns:dc="http://www.omg.org/spec/UML/20131001/UMLDC" \
xmlns:SysML="http://www.omg.org/spec/SysML/20161101/SysML" xmlns:EARL="http://www.sparxsystems.com/profiles/EARL/1.0">
	<xmi:Documentation exporter="Enterprise Architect" exporterVersion="6.5"/>
	<uml:Model xmi:type="uml:Model" name="EA_Model">
		<packagedElement xmi:type="uml:Package" xmi:id="EAPK_M" name="Model">
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_C" name="Asset">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_A" name="removed">
					<lowerValue xmi:type="uml:LiteralInteger" xmi:id="EAID_LI000001_A" value="0"/>
					<upperValue xmi:type="uml:LiteralUnlimitedNatural" xmi:id="EAID_LI000002_A" value="1"/>
					<type xmi:idref="EAJava_boolean"/>
				</ownedAttribute>
			</packagedElement>
		</packagedElement>
		<umldi:Diagram xmi:type="umldi:UMLClassDiagram" xmi:id="EAID_D" isFrame="true" modelElement="EAPK_M"/>
	</uml:Model>
	<xmi:Extension extender="Enterprise Architect" extenderID="6.5">
		<elements><element xmi:idref="EAID_C" xmi:type="uml:Class" name="Asset"/></elements>
	</xmi:Extension>
	<SysML:block base_Class="EAID_C"/>
	<EARL:Agent base_Class="EAID_C"/>
</xmi:XMI>
"""


def write(tmp_path: Path, text: str, name: str = "model.xml") -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode("cp1252"))
    return path


@pytest.fixture
def raw(tmp_path: Path) -> RawModel:
    return load_raw_model(write(tmp_path, EA21))


def by_id(raw: RawModel, element_id: str):
    return raw.by_id[element_id]


# -- detection, identity, encoding ---------------------------------------------------------------

def test_an_xmi_21_export_is_read_as_the_enterprise_architect_dialect(raw: RawModel) -> None:
    assert raw.dialect == "enterprise-architect"


def test_an_export_with_the_ea_2013_namespaces_is_read_as_the_same_dialect(tmp_path: Path) -> None:
    raw = load_raw_model(write(tmp_path, EA2013))
    assert raw.dialect == "enterprise-architect"
    assert raw.has_sysml(by_id(raw, "EAID_C"), "Block")
    assert [app.name for app in raw.applied(by_id(raw, "EAID_C"))] == ["block", "Agent"]


def test_a_declared_windows_1252_encoding_gives_non_ascii_names_and_guards(raw: RawModel) -> None:
    assert raw.name(by_id(raw, "EAID_SYS")) == "Gerätezelle"
    spec = by_id(raw, "EAID_OE000000_T1")
    assert raw.opaque_bodies(spec) == [("", "¬stop/pp")]


def test_ids_repeated_in_the_extension_are_ignored_and_its_tool_types_never_read(raw: RawModel) -> None:
    assert raw.diagnostics == []
    assert raw.uml_type(by_id(raw, "EAID_K1")) == "Connector"
    assert raw.uml_type(by_id(raw, "EAID_P_CS")) == "Property"
    assert "EAJava_double" not in raw.by_id  # defined under xmi:Extension/primitivetypes only


def test_the_ea_model_wrapper_is_not_the_model_the_exported_package_is(raw: RawModel) -> None:
    assert raw.model_name == "Cell"
    model = lift(raw).model
    assert model.name == "Cell"
    assert list(model.datatypes) == ["Command", "Integer", "Real"]


# -- stereotypes ------------------------------------------------------------------------------------

def test_stereotype_applications_inside_the_model_are_found_without_ids(raw: RawModel) -> None:
    assert raw.has_sysml(by_id(raw, "EAID_AGENT"), "Block")
    agent = raw.applied(by_id(raw, "EAID_AGENT"))
    assert [(a.family, a.name, a.tags) for a in agent] == [
        ("sysml", "block", {}),
        ("earl", "Agent", {"declaredType": "CE"}),
    ]


def test_the_stereotype_name_comes_from_ea_stereo_name_and_is_no_tag(raw: RawModel) -> None:
    (app,) = raw.applied(by_id(raw, "EAID_T1"))
    assert (app.name, app.tags) == ("Fsm Transition", {"priority": "2"})


def test_base_attribute_extends_an_attribute_and_other_profiles_stay_other(raw: RawModel) -> None:
    (memory,) = raw.applied(by_id(raw, "EAID_HIST"))
    assert (memory.family, memory.name) == ("earl", "Internal Memory")
    (note,) = raw.applied(by_id(raw, "EAID_SPEED"))
    assert note.family == "other"


# -- types and multiplicities -----------------------------------------------------------------------

def test_types_given_as_idref_children_resolve_and_eajava_primitives_are_known_by_name(raw: RawModel) -> None:
    assert raw.ref(by_id(raw, "EAID_CS_OUT"), "type") is by_id(raw, "EAID_CMD")
    assert raw.ref(by_id(raw, "EAID_SPEED"), "type") == ExternalRef("#EAJava_double")
    command = lift(raw).model.datatypes["Command"]
    assert [(f.name, f.type) for f in command.fields] == [("speed", "Real"), ("axes", "Integer")]


def test_minus_one_is_unbounded_and_literal_integer_uppers_are_bounds(raw: RawModel) -> None:
    assert multiplicity(raw, by_id(raw, "EAID_SPEED")) == (0, None)
    assert multiplicity(raw, by_id(raw, "EAID_AXES")) == (3, 3)
    assert multiplicity(raw, by_id(raw, "EAID_P_DRIVE")) == (2, 2)
    assert multiplicity(raw, by_id(raw, "EAID_P_CS")) == (1, 1)


# -- ports and connector ends -----------------------------------------------------------------------

def test_a_qualifier_port_copy_stands_for_the_port_of_the_parts_type(raw: RawModel) -> None:
    end = resolve_end(raw, by_id(raw, "EAID_DS000000_K1"))
    assert (end.role, end.part_with_port, end.path) == (by_id(raw, "EAID_DRIVE_IN"), by_id(raw, "EAID_P_DRIVE"), ())
    assert raw.is_copy(by_id(raw, "EAID_Q_DRIVE_IN")) and not raw.is_copy(by_id(raw, "EAID_DRIVE_IN"))


def test_copies_of_copies_give_the_path_through_the_nested_parts(raw: RawModel) -> None:
    end = resolve_end(raw, by_id(raw, "EAID_SC000000_K2"))
    assert end.role is by_id(raw, "EAID_CS_OUT")
    assert end.part_with_port is by_id(raw, "EAID_P_CS")
    assert end.path == (by_id(raw, "EAID_P_A"), by_id(raw, "EAID_P_CS"))


def test_ports_written_as_owned_ports_become_buffers_and_copies_become_links(raw: RawModel) -> None:
    (system,) = lift(raw).model.systems
    assert system.name == "Gerätezelle" and system.recognised_by == "stereotype"
    agent = system.agents[0]
    assert agent.declared_type == "CE" and agent.recognised_by == "stereotype"
    cs = agent.subsystems[0]
    assert (cs.kind, cs.recognised_by) == ("cs", "stereotype")
    assert [b.name for b in cs.outputs] == ["cmd/ob"] and [b.name for b in cs.inputs] == ["cmd/ib"]
    assert [(m.name, m.recognised_by) for m in cs.memory] == [("history/m", "stereotype")]
    assert [link.ends for link in agent.links] == [
        ("a/a.cs.cmd/ob", "a/a.drive1/ve.cmd/ib"),
        ("a/a.cs.cmd/ob", "a/a.drive2/ve.cmd/ib"),
    ]
    assert [(link.source, link.target) for link in system.links] == [("a/a.cs.cmd/ob", "b/a.cs.cmd/ib")]


# -- state machines ---------------------------------------------------------------------------------

def test_without_classifier_behavior_the_first_owned_state_machine_is_the_fsm(raw: RawModel) -> None:
    cs = lift(raw).model.systems[0].agents[0].subsystems[0]
    assert cs.fsm is not None and cs.fsm.name == "fsm" and cs.fsm.initial == "idle"
    assert [s.name for s in cs.fsm.states] == ["idle", "run"]


def test_an_inline_guard_with_a_body_attribute_is_the_transition_condition(raw: RawModel) -> None:
    cs = lift(raw).model.systems[0].agents[0].subsystems[0]
    assert cs.fsm is not None
    (transition,) = cs.fsm.transitions
    assert transition.condition is not None and transition.condition.text == "¬stop/pp"
    assert transition.condition.language == "" and transition.priority == 2
    assert [(p.name, p.fun.text if p.fun else None) for p in cs.predicates] == [("stop/pp", "FALSE")]


# -- the command line -------------------------------------------------------------------------------

@pytest.mark.parametrize("command", ["show", "check", "stats"])
def test_the_commands_read_an_ea_file_without_a_traceback(tmp_path: Path, command: str) -> None:
    path = write(tmp_path, EA21)
    result = subprocess.run([sys.executable, "-m", "earl_m2t", command, str(path)], cwd=ROOT,
                            capture_output=True, text=True, timeout=120)
    assert "Traceback" not in result.stderr and result.returncode in (0, 1), result.stderr
    if command == "show":
        assert result.stdout.splitlines()[0].startswith("model Cell  (enterprise-architect) ")


def test_the_api_loads_an_ea_file_as_an_earl_model(tmp_path: Path) -> None:
    loaded = load(write(tmp_path, EA21))
    assert loaded.model.dialect == "enterprise-architect" and loaded.model.has_earl_content


# -- what EA keeps in its xmi:Extension records -----------------------------------------------------

# EA writes an opaque behaviour's text as body="…" without a language: the language is the
# element's Language, <code gentype="…"/> in its record under xmi:Extension/elements ("<none>"
# when unset). Transitions and connectors come after their source element; their records under
# xmi:Extension/connectors number them as they were created (<model ea_localid>).
EA_RECORDS = """<?xml version="1.0" encoding="windows-1252"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1" \
xmlns:EARL="http://www.sparxsystems.com/profiles/EARL/1.0">
	<xmi:Documentation exporter="Enterprise Architect" exporterVersion="6.5"/>
	<uml:Model xmi:type="uml:Model" name="EA_Model" visibility="public">
		<packagedElement xmi:type="uml:Package" xmi:id="EAPK_P" name="P" visibility="public">
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_CS" name="Control" visibility="public">
				<ownedBehavior xmi:type="uml:StateMachine" xmi:id="EAID_SM" name="fsm" visibility="public">
					<region xmi:type="uml:Region" xmi:id="EAID_SR000001_P" name="EA_Region1" visibility="public">
						<subvertex xmi:type="uml:Pseudostate" xmi:id="EAID_I" name="Initial" kind="initial"/>
						<transition xmi:type="uml:Transition" xmi:id="EAID_T0" kind="local" source="EAID_I" target="EAID_A"/>
						<subvertex xmi:type="uml:State" xmi:id="EAID_A" name="a"/>
						<transition xmi:type="uml:Transition" xmi:id="EAID_T_AB" name="a,b/t" kind="local" source="EAID_A" target="EAID_B"/>
						<transition xmi:type="uml:Transition" xmi:id="EAID_T_AA" name="a,a/t" kind="local" source="EAID_A" target="EAID_A"/>
						<subvertex xmi:type="uml:State" xmi:id="EAID_B" name="b"/>
						<transition xmi:type="uml:Transition" xmi:id="EAID_T_BA" name="b,a/t" kind="local" source="EAID_B" target="EAID_A">
							<guard xmi:type="uml:Constraint" xmi:id="EAID_CO000000_T_BA">
								<specification xmi:type="uml:OpaqueExpression" xmi:id="EAID_OE000000_T_BA" body="ready/pp"/>
							</guard>
						</transition>
					</region>
				</ownedBehavior>
				<ownedBehavior xmi:type="uml:OpaqueBehavior" xmi:id="EAID_PP" name="ready/pp" visibility="public" body="TRUE"/>
				<ownedBehavior xmi:type="uml:OpaqueBehavior" xmi:id="EAID_PP_CPP" name="busy/pp" visibility="public" body="return busy();"/>
				<ownedBehavior xmi:type="uml:OpaqueBehavior" xmi:id="EAID_PF" name="step/pf" visibility="public" body="// step"/>
				<ownedBehavior xmi:type="uml:OpaqueBehavior" xmi:id="EAID_PF_NONE" name="idle/pf" visibility="public" body="// idle"/>
				<ownedRule xmi:type="uml:Constraint" xmi:id="EAID_RULE" name="limit" visibility="public">
					<specification xmi:type="uml:OpaqueExpression" xmi:id="EAID_OE000000_RULE" body="speed &lt; 2"/>
				</ownedRule>
			</packagedElement>
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_AG" name="Unit" visibility="public">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_AG_CS" name="cs" visibility="public" aggregation="composite">
					<type xmi:idref="EAID_CS"/>
				</ownedAttribute>
			</packagedElement>
			<packagedElement xmi:type="uml:Class" xmi:id="EAID_SYS" name="Cell" visibility="public">
				<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_SYS_AG" name="unit" visibility="public" aggregation="composite">
					<type xmi:idref="EAID_AG"/>
				</ownedAttribute>
			</packagedElement>
		</packagedElement>
		<EARL:System base_Class="EAID_SYS"/>
		<EARL:Agent base_Class="EAID_AG"/>
		<EARL:ControlSubsystem base_Class="EAID_CS"/>
		<EARL:PrimitivePredicate base_Behavior="EAID_PP"/>
		<EARL:PrimitivePredicate base_Behavior="EAID_PP_CPP"/>
		<EARL:PartialTransitionFunction base_Behavior="EAID_PF"/>
		<EARL:PartialTransitionFunction base_Behavior="EAID_PF_NONE"/>
	</uml:Model>
	<xmi:Extension extender="Enterprise Architect" extenderID="6.5">
		<elements>
			<element xmi:idref="EAID_CS" xmi:type="uml:Class" name="Control" scope="public">
				<model package="EAPK_P" tpos="1" ea_localid="1" ea_eleType="element"/>
				<code gentype="Java"/>
			</element>
			<element xmi:idref="EAID_PP" xmi:type="uml:OpaqueBehavior" name="ready/pp" scope="public">
				<model package="EAPK_P" owner="EAID_CS" tpos="2" ea_localid="3" ea_eleType="element"/>
				<code gentype="EARL"/>
			</element>
			<element xmi:idref="EAID_PP_CPP" xmi:type="uml:OpaqueBehavior" name="busy/pp" scope="public">
				<model package="EAPK_P" owner="EAID_CS" tpos="3" ea_localid="4" ea_eleType="element"/>
				<code gentype="C++"/>
			</element>
			<element xmi:idref="EAID_PF" xmi:type="uml:OpaqueBehavior" name="step/pf" scope="public">
				<model package="EAPK_P" owner="EAID_CS" tpos="4" ea_localid="5" ea_eleType="element"/>
				<code product_name="C++" gentype="C++"/>
			</element>
			<element xmi:idref="EAID_PF_NONE" xmi:type="uml:OpaqueBehavior" name="idle/pf" scope="public">
				<model package="EAPK_P" owner="EAID_CS" tpos="5" ea_localid="6" ea_eleType="element"/>
				<code gentype="&lt;none&gt;"/>
			</element>
			<element xmi:idref="EAID_RULE" xmi:type="uml:Constraint" name="limit" scope="public">
				<model package="EAPK_P" owner="EAID_CS" tpos="6" ea_localid="7" ea_eleType="element"/>
				<code gentype="EARL"/>
			</element>
		</elements>
		<connectors>
			<connector xmi:idref="EAID_T0"><source xmi:idref="EAID_I"><model ea_localid="8"/></source><model ea_localid="1"/></connector>
			<connector xmi:idref="EAID_T_AB"><source xmi:idref="EAID_A"><model ea_localid="9"/></source><model ea_localid="4"/></connector>
			<connector xmi:idref="EAID_T_AA"><source xmi:idref="EAID_A"><model ea_localid="9"/></source><model ea_localid="3"/></connector>
			<connector xmi:idref="EAID_T_BA"><source xmi:idref="EAID_B"><model ea_localid="10"/></source><model ea_localid="2"/></connector>
		</connectors>
	</xmi:Extension>
</xmi:XMI>
"""


@pytest.fixture
def records(tmp_path: Path) -> RawModel:
    return load_raw_model(write(tmp_path, EA_RECORDS, "records.xml"))


def test_the_extension_record_gives_an_element_s_properties_and_only_its_own(records: RawModel) -> None:
    assert records.extension_property(by_id(records, "EAID_PF"), "language") == "C++"
    assert records.extension_property(by_id(records, "EAID_CS"), "language") == "Java"
    assert records.extension_property(by_id(records, "EAID_PF_NONE"), "language") == ""  # "<none>": not set
    assert records.extension_property(by_id(records, "EAID_T_AB"), "created") == "4"  # not its source end's 9
    assert records.extension_property(by_id(records, "EAID_SM"), "language") == ""  # no record
    assert "EAID_PF" in records.by_id and records.diagnostics == []  # the records repeat ids: not indexed


def test_an_opaque_body_without_language_takes_the_element_s_language(records: RawModel) -> None:
    assert records.opaque_bodies(by_id(records, "EAID_PF")) == [("C++", "// step")]
    assert records.opaque_bodies(by_id(records, "EAID_PF_NONE")) == [("", "// idle")]
    # an expression has no record: it takes the Language of the Constraint it specifies
    assert records.opaque_bodies(by_id(records, "EAID_OE000000_RULE")) == [("EARL", "speed < 2")]
    # a guard is no element in EA, its transition a connector: no language
    assert records.opaque_bodies(by_id(records, "EAID_OE000000_T_BA")) == [("", "ready/pp")]


def test_pf_and_pp_languages_come_from_the_records(records: RawModel) -> None:
    (cs,) = lift(records).model.subsystems
    assert [(pf.name, pf.language) for pf in cs.functions] == [("step/pf", "C++"), ("idle/pf", "")]
    predicates = {pp.name: pp for pp in cs.predicates}
    assert predicates["ready/pp"].language == "EARL" and predicates["ready/pp"].fun is not None
    assert predicates["busy/pp"].language == "C++" and predicates["busy/pp"].fun is None  # user code


def test_transitions_are_lifted_in_the_order_ea_created_them(records: RawModel) -> None:
    region = by_id(records, "EAID_SR000001_P")
    in_file = records.children(region, "transition")
    assert [records.xmi_id(t) for t in in_file] == ["EAID_T0", "EAID_T_AB", "EAID_T_AA", "EAID_T_BA"]
    assert [records.xmi_id(t) for t in records.in_connector_order(in_file)] == [
        "EAID_T0", "EAID_T_BA", "EAID_T_AA", "EAID_T_AB",
    ]
    (cs,) = lift(records).model.subsystems
    assert cs.fsm is not None
    assert [t.name for t in cs.fsm.transitions] == ["b,a/t", "a,a/t", "a,b/t"]
    assert [t.order for t in cs.fsm.transitions] == [0, 1, 2]


def test_without_a_number_for_each_the_file_order_stays(raw: RawModel) -> None:
    """The EA21 file's extension has records for some elements only, none for transitions."""
    region = by_id(raw, "EAID_SR000001_SM")
    in_file = raw.children(region, "transition")
    assert raw.in_connector_order(in_file) == in_file
    assert raw.opaque_bodies(by_id(raw, "EAID_STOP")) == [("", "FALSE")]

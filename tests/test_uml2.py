"""The Papyrus side read by the real Eclipse UML2 (the library Papyrus saves and loads with).

``tests/uml2/Uml2Check.java`` runs on Eclipse UML2 5.0 and EMF from Maven Central
(``tests/uml2/pom.xml``; Maven caches the jars in ``~/.m2``, outside the checkout). It loads the
profile ``earl-m2t profile --format papyrus`` writes and the Papyrus sample applying it, and
prints what is asserted here:

- the profile is a defined profile, loaded without error or warning;
- the sample loads without error or warning and every EARL stereotype application resolves
  (its stereotype and its base element);
- UML2's Diagnostician finds nothing but what the SysML profile causes, which Maven Central
  does not carry: the unresolved references to it (profile applications, Papyrus's
  annotations), and the inter-agent connectors, whose ends reach the agents' control
  subsystems through SysML's NestedConnectorEnd (``propertyPath``), which plain UML does not
  know (docs/modelling-guide.md, "Checking the Papyrus files with Eclipse UML2").

``./dev test`` installs a JDK and Maven when they are missing.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from lxml import etree

ROOT = Path(__file__).resolve().parents[1]
UML2 = ROOT / "tests" / "uml2"
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
# the Papyrus samples, by name: the file and its model's name; each applies the profile beside the
# reference sample (two_arm.uml and harmoniser.uml name ../pick_and_place/EARL.profile.uml)
SAMPLES = {
    "pick_and_place": (SAMPLE, "PickAndPlace"),
    "two_arm": (ROOT / "samples" / "two_arm" / "two_arm.uml", "TwoArm"),
    "harmoniser": (ROOT / "samples" / "harmoniser" / "harmoniser.uml", "Harmoniser"),
}
# each Papyrus sample's inter-agent links: the connectors with SysML NestedConnectorEnds
INTER_AGENT_LINKS = {"pick_and_place": 4, "two_arm": 4, "harmoniser": 5}
EARL_NS = "http:///schemas/EARL/"
SYSML_NS = "http://www.eclipse.org/papyrus/sysml/"
XMI_ID = "{http://www.omg.org/spec/XMI/20131001}id"

pytestmark = pytest.mark.skipif(
    not (shutil.which("javac") and shutil.which("java") and shutil.which("mvn")),
    reason="a JDK and Maven are needed (./dev test installs them)",
)


@dataclass
class Uml2Report:
    profile: dict[str, str] = field(default_factory=dict)
    model: dict[str, str] = field(default_factory=dict)
    load_problems: list[str] = field(default_factory=list)
    applications: dict[str, str] = field(default_factory=dict)
    unresolved: list[str] = field(default_factory=list)
    diagnostics: list[tuple[str, str, str]] = field(default_factory=list)  # severity, element, message


def _fields(text: str) -> dict[str, str]:
    return dict(item.split("=", 1) for item in text.split() if "=" in item)


def parse(output: str) -> Uml2Report:
    report = Uml2Report()
    for line in output.splitlines():
        kind, _, rest = line.partition(" ")
        if kind in ("profile", "model"):
            name, _, facts = rest.partition(" ")
            setattr(report, kind, {"name": name, **_fields(facts)})
        elif kind in ("load-error", "load-warning"):
            report.load_problems.append(line)
        elif kind == "earl-applications":
            report.applications = _fields(rest)
        elif kind == "unresolved":
            report.unresolved.append(rest)
        elif kind == "diagnostic":
            severity, _, tail = rest.partition(" ")
            element, _, message = tail.partition(" | ")
            report.diagnostics.append((severity, element, message))
    return report


def _run(command: list[str], **kwargs: object) -> subprocess.CompletedProcess[str]:
    run = subprocess.run(command, capture_output=True, text=True, check=False, **kwargs)  # type: ignore[call-overload]
    assert run.returncode == 0, f"{' '.join(command[:3])} … failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    return run


@pytest.fixture(scope="module")
def uml2_check(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """Uml2Check compiled: its classes folder and the class path of UML2 and EMF."""
    work = tmp_path_factory.mktemp("uml2")
    classpath_file = work / "classpath.txt"
    _run(["mvn", "-B", "-q", "-f", str(UML2 / "pom.xml"), "dependency:build-classpath",
          f"-Dmdep.outputFile={classpath_file}"])
    classpath = classpath_file.read_text(encoding="utf-8").strip()
    classes = work / "classes"
    _run(["javac", "-nowarn", "-d", str(classes), "-cp", classpath, str(UML2 / "Uml2Check.java")])
    return classes, classpath


@pytest.fixture(scope="module", params=list(SAMPLES))
def checked(request: pytest.FixtureRequest, uml2_check: tuple[Path, str],
            tmp_path_factory: pytest.TempPathFactory) -> tuple[str, Uml2Report]:
    classes, classpath = uml2_check
    sample: str = request.param
    path = SAMPLES[sample][0]
    # the samples folder as in the checkout, the profile as earl-m2t generates it beside the
    # reference sample (the samples' hrefs name that EARL.profile.uml)
    samples = tmp_path_factory.mktemp("samples")
    profile_dir = samples / "pick_and_place"
    _run([sys.executable, "-m", "earl_m2t", "profile", "--format", "papyrus", "-o", str(profile_dir)])
    (samples / sample).mkdir(exist_ok=True)
    shutil.copy(path, samples / sample / path.name)
    run = _run(["java", "-cp", f"{classes}:{classpath}", "Uml2Check", str(profile_dir / "EARL.profile.uml"),
                str(samples / sample / path.name)])
    return sample, parse(run.stdout)


def _sample_facts(sample: str) -> tuple[int, set[str]]:
    """The sample's EARL stereotype applications, and the connectors whose ends are SysML
    NestedConnectorEnds."""
    root = etree.parse(str(SAMPLES[sample][0])).getroot()
    applications = [el for el in root if isinstance(el.tag, str) and el.tag.startswith(f"{{{EARL_NS}")]
    nested_ends = {el.get("base_ConnectorEnd") for el in root
                   if isinstance(el.tag, str) and el.tag.startswith(f"{{{SYSML_NS}")
                   and etree.QName(el).localname == "NestedConnectorEnd"}
    connectors = {connector.get(XMI_ID) for connector in root.iter("ownedConnector")
                  if any(end.get(XMI_ID) in nested_ends for end in connector.iter("end"))}
    return len(applications), connectors


def test_the_generated_profile_is_a_defined_profile_loaded_without_problems(
    checked: tuple[str, Uml2Report],
) -> None:
    _, report = checked
    assert report.profile == {"name": "EARL", "defined": "true", "errors": "0", "warnings": "0"}


def test_the_sample_loads_without_problems_and_every_earl_application_resolves(
    checked: tuple[str, Uml2Report],
) -> None:
    sample, report = checked
    assert report.model == {"name": SAMPLES[sample][1], "errors": "0", "warnings": "0"}
    assert report.load_problems == []
    applications, _ = _sample_facts(sample)
    assert applications > 50
    assert report.applications == {"total": str(applications), "resolved": str(applications)}
    assert report.unresolved == []


def test_diagnostician_finds_only_what_the_missing_sysml_profile_causes(checked: tuple[str, Uml2Report]) -> None:
    sample, report = checked
    _, nested = _sample_facts(sample)
    assert len(nested) == INTER_AGENT_LINKS[sample]
    connector_warnings = set()
    others = []
    for severity, element, message in report.diagnostics:
        if "SysML" in message and "unresolved proxy" in message:
            continue  # a reference into the SysML profile or its EPackage, not on Maven Central
        found = re.search(r"The owner of connector '.*#([^}']+)\}' must also own the connected roles", message)
        if severity == "WARNING" and found:
            connector_warnings.add(found.group(1))
            continue
        others.append((severity, element, message))
    assert others == []
    assert connector_warnings == nested

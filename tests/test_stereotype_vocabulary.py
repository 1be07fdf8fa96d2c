"""Stereotypes named as the EARL authors' EA profile names them, and profiles that specialise EARL.

The sample variants of ``samples/pick_and_place/variants/`` (``scripts/make_sample.py``) are the
Enterprise Architect sample with other stereotypes: the authors' MDG names (``EARL:ContSubsys``)
and SPSysML's specialised ones (``SPSys:PhyContSubsys``), which mean EARL concepts only through
SPSysML's profile file (``../shared/profiles/spsysml-spsys-profile.xml`` beside the checkout).
Each must lift to the sample's ``show --format json``.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from earl_m2t.api import check, load
from earl_m2t.diagnostics import ModelReadError
from earl_m2t.export import model_to_dict
from earl_m2t.profile import load_profile
from earl_m2t.stereotypes.ea_profile import read_profile_file
from earl_m2t.stereotypes.vocabulary import Vocabulary
from tests.test_sample_dialects_equal import FILES, without_location

ROOT = Path(__file__).resolve().parents[1]
VARIANTS = ROOT / "samples" / "pick_and_place" / "variants"
AUTHORS = VARIANTS / "pick_and_place.earl-mdg.ea.xml"
SPSYS = VARIANTS / "pick_and_place.spsys.ea.xml"
SPSYS_PROFILE = ROOT.parent / "shared" / "profiles" / "spsysml-spsys-profile.xml"
needs_spsys_profile = pytest.mark.skipif(not SPSYS_PROFILE.is_file(), reason="SPSysML profile not beside the checkout")


def lifted(path: Path, profiles: tuple[Path, ...] = ()) -> dict[str, Any]:
    return without_location(model_to_dict(load(path, profiles=profiles).model))


@pytest.fixture(scope="module")
def sample() -> dict[str, Any]:
    return lifted(FILES["ea"])


def test_the_variants_use_other_stereotypes_than_the_sample() -> None:
    authors, spsys = AUTHORS.read_text("windows-1252"), SPSYS.read_text("windows-1252")
    assert "<EARL:ContSubsys " in authors and "<EARL:ControlSubsystem " not in authors
    assert "<SPSys:PhyContSubsys " in spsys and "<EARL:ControlSubsystem " not in spsys
    assert "<SPSys:PhyAgent " in spsys and "<SPSys:PhyVirtEff " in spsys and "<SPSys:PhyRealEff " in spsys


def test_the_authors_names_lift_like_the_sample(sample: dict[str, Any]) -> None:
    assert lifted(AUTHORS) == sample
    assert [str(d) for d in check(AUTHORS)] == []


@pytest.mark.parametrize("dialect", ["papyrus", "cameo"])
def test_the_authors_names_are_recognised_in_every_dialect(dialect: str, tmp_path: Path,
                                                           sample: dict[str, Any]) -> None:
    text = FILES[dialect].read_text(encoding="utf-8")
    for concept, name in (("ControlSubsystem", "ContSubsys"), ("VirtualEffector", "VirtEff"),
                          ("RealEffector", "RealEff")):
        assert f"<EARL:{concept} " in text
        text = text.replace(f"<EARL:{concept} ", f"<EARL:{name} ")
    renamed = tmp_path / FILES[dialect].name
    renamed.write_text(text, encoding="utf-8")
    assert lifted(renamed) == lifted(FILES[dialect])


@needs_spsys_profile
def test_the_spsysml_profile_teaches_its_specialised_stereotypes() -> None:
    base = Vocabulary(tuple(load_profile().concepts))
    (profile,) = read_profile_file(SPSYS_PROFILE, base.earl_concept)
    assert profile.name == "SPSys"
    assert {name: profile.concept(name) for name in (
        "PhyAgent", "SimAgent", "HybAgent", "PhyContSubsys", "SimPhyContSubsys", "SimVirtEff", "PhyVirtRec",
        "PhyRealEff", "SimRealRec", "PhyDriverGpSubsys", "MirrSimGpAgents",
    )} == {
        "PhyAgent": "Agent", "SimAgent": "Agent", "HybAgent": "Agent", "PhyContSubsys": "ControlSubsystem",
        "SimPhyContSubsys": "ControlSubsystem", "SimVirtEff": "VirtualEffector", "PhyVirtRec": "VirtualReceptor",
        "PhyRealEff": "RealEffector", "SimRealRec": "RealReceptor", "PhyDriverGpSubsys": "SubsystemGroup",
        "MirrSimGpAgents": "AgentGroup",
    }
    assert profile.concept("CompFunReq") == "" and profile.concept("Requirement") == ""


@needs_spsys_profile
def test_spsysml_stereotypes_with_the_profile_given_lift_like_the_sample(sample: dict[str, Any]) -> None:
    assert lifted(SPSYS, (SPSYS_PROFILE,)) == sample


def test_spsysml_stereotypes_without_their_profile_are_not_earl_stereotypes(sample: dict[str, Any]) -> None:
    model = load(SPSYS).model
    agents = model.systems[0].agents
    assert {agent.recognised_by for agent in agents} == {"suffix"}
    assert lifted(SPSYS) != sample


@needs_spsys_profile
def test_a_profile_file_beside_the_model_is_read_without_the_option(tmp_path: Path, sample: dict[str, Any]) -> None:
    shutil.copy(SPSYS, tmp_path / SPSYS.name)
    shutil.copy(SPSYS_PROFILE, tmp_path / "spsys-profile.xml")
    assert lifted(tmp_path / SPSYS.name) == sample


def test_a_file_that_is_no_profile_is_one_line_and_exit_2(tmp_path: Path) -> None:
    bogus = tmp_path / "mine.xml"
    bogus.write_text("<notes><note/></notes>\n", encoding="utf-8")
    with pytest.raises(ModelReadError, match="not an Enterprise Architect profile file"):
        load(SPSYS, profiles=(bogus,))
    run = subprocess.run([sys.executable, "-m", "earl_m2t", "show", str(SPSYS), "--profile", str(bogus)],
                         capture_output=True, text=True, check=False)
    assert run.returncode == 2 and run.stdout == ""
    assert run.stderr.count("\n") == 1 and f"{bogus}:1: error: not an Enterprise Architect profile" in run.stderr


def test_a_broken_profile_beside_the_model_is_reported(tmp_path: Path) -> None:
    shutil.copy(SPSYS, tmp_path / SPSYS.name)
    (tmp_path / "spsys-profile.xml").write_text("<UMLProfile><Documentation", encoding="utf-8")
    with pytest.raises(ModelReadError, match="spsys-profile.xml.*not well-formed XML"):
        load(tmp_path / SPSYS.name)

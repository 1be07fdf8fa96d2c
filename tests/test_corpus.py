"""Every file of the shared corpus of real third-party models goes through ``show``, ``check`` and
``stats``: no traceback, the expected dialect, the documented exit codes, in reasonable time.

The corpus (``../shared/corpus`` beside the checkout, see its README) holds no EARL model, so
``check`` reports R003 on every file it can read, and R004 once for each resource a file
references that is not at hand (the rest of those projects, Eclipse workspace paths, pathmaps of
other plug-ins). The tests are skipped without the corpus.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CORPUS = ROOT.parent / "shared" / "corpus"
SECONDS = 60  # per command; the largest file (a 7.5 MB MagicDraw model) takes well under a second

# relative path (or folder/) -> the dialect `show` reports, or the one-line reason it cannot read the file
READ = {
    "papyrus/": "papyrus",
    "other/papyrus-uml-marte-no-sysml-producer-consumer.uml": "papyrus",
    "cameo/cameo-to-capella-md-emf-uml2-export.uml": "cameo-eclipse-uml2",
    "cameo/": "cameo",  # the .mdzip projects and their model members
    "ea/": "enterprise-architect",
}
# relative path -> the resources (href before '#') that R004 reports, once each; none for the others
UNRESOLVED = {
    "cameo/arrowhead-tank-control-md19-model.xmi": {
        "Arrowhead_core_JD15d_experimental.mdzip", "Arrowhead Profile-JD-84b_experimental.mdzip",
    },
    "cameo/arrowhead-tank-control-md19.mdzip": {
        "Arrowhead_core_JD15d_experimental.mdzip", "Arrowhead Profile-JD-84b_experimental.mdzip",
    },
    "cameo/cameo-to-capella-md-emf-uml2-export.uml": {
        "SysML.profile.uml", "UML_Standard_Profile.MagicDraw_Profile.DSL_Customization.profile.uml",
        "MD_Customization_for_SysML.additional_stereotypes.profile.uml",
    },
    "other/papyrus-uml-marte-no-sysml-producer-consumer.uml": {
        "pathmap://QML_CORE/core.uml", "pathmap://QML_CORE/corba.uml", "pathmap://QML_CORE/fifo.uml",
        "pathmap://QML_CORE/sysinterfaces.uml",
    },
    "papyrus/arrowhead-5.0-dsl-sysml16.uml": {
        "../EclipseArrowhead/EclipseArrowhead_v5.0.uml", "../JD3.ArrowheadMetamodel/ArrowheadMetamodel_JD-v6.uml",
    },
    "papyrus/arrowhead-principles-sysml16.uml": {"platform:/resource/EclipseArrowhead/EclipseArrowhead_v6.uml"},
    "papyrus/robotml-robocab-sysml-papyrus07.uml": {
        "pathmap://Robotml_LIBRARIES/RobotMLPlatformLibraries.uml",
        "pathmap://Robotml_LIBRARIES/RobotmlPlatformLibraries.uml", "pathmap://Papyrus_Alf_LIBRARIES/alflibrary.uml",
    },
}
REFUSED = {
    "other/sysmlv2-xmi-ports-library.sysmlx": "SysML v2 XMI (.sysmlx) is not supported",
    "sysmlv2/": "SysML v2 textual models are not supported yet",
}


def corpus_files() -> list[str]:
    if not CORPUS.is_dir():
        return []
    return sorted(str(p.relative_to(CORPUS)) for p in CORPUS.rglob("*") if p.is_file() and p.name != "README.md")


def expected(relative: str, table: dict[str, str]) -> str | None:
    """The entry for a file: its own row first, else its folder's."""
    if relative in table:
        return table[relative]
    return next((value for key, value in table.items() if key.endswith("/") and relative.startswith(key)), None)


def earl(*args: str) -> tuple[subprocess.CompletedProcess[str], float]:
    start = time.monotonic()
    result = subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                            timeout=SECONDS * 2)
    return result, time.monotonic() - start


def no_traceback(result: subprocess.CompletedProcess[str]) -> None:
    text = result.stdout + result.stderr
    assert "Traceback" not in text and "internal error" not in text, text[-2000:]


needs_corpus = pytest.mark.skipif(not CORPUS.is_dir(), reason="shared corpus not beside the checkout")


@needs_corpus
def test_every_corpus_file_has_an_expectation() -> None:
    files = corpus_files()
    assert files
    for relative in files:
        in_read = expected(relative, READ) is not None and relative not in REFUSED
        in_refused = expected(relative, REFUSED) is not None
        assert in_read or in_refused, f"{relative}: add it to READ or REFUSED"


@needs_corpus
@pytest.mark.parametrize("relative", corpus_files())
def test_a_corpus_file_is_shown_checked_and_counted_without_a_traceback(relative: str) -> None:
    path = str(CORPUS / relative)
    refused = REFUSED.get(relative) or (None if relative in READ else expected(relative, REFUSED))
    shown, shown_time = earl("show", "--format", "json", path)
    checked, checked_time = earl("check", path)
    counted, counted_time = earl("stats", "--format", "json", path)
    for result in (shown, checked, counted):
        no_traceback(result)
    assert shown_time < SECONDS and checked_time < SECONDS and counted_time < SECONDS
    if refused is not None:
        for result in (shown, checked, counted):
            assert result.returncode == 2, result.stderr
            assert result.stderr.count("\n") == 1 and result.stderr.startswith(path)
            assert refused in result.stderr
        assert shown.stdout == "" and counted.stdout == ""
        return
    assert counted.returncode == 0, counted.stderr
    assert json.loads(counted.stdout)["dialect"] == expected(relative, READ)
    assert shown.returncode == 0, shown.stderr
    document = json.loads(shown.stdout)
    assert document["dialect"] == expected(relative, READ)
    assert document["earl"] is False and document["systems"] == []
    assert checked.returncode == 1, checked.stdout + checked.stderr
    findings = [line for line in checked.stdout.splitlines()[:-1]]
    assert len([f for f in findings if " R003 error: " in f]) == 1, checked.stdout
    unresolved = [f.partition(" R004 warning: unresolved reference ")[2] for f in findings if " R004 " in f]
    resources = [f.partition("#")[0] for f in unresolved]
    assert len(findings) == 1 + len(resources), checked.stdout
    assert sorted(resources) == sorted(UNRESOLVED.get(relative, ())), checked.stdout
    warnings = len(resources)
    assert checked.stdout.splitlines()[-1] == f"1 file checked: 1 error(s), {warnings} warning(s), 0 info"


@needs_corpus
def test_an_mdzip_and_its_model_member_give_the_same_model() -> None:
    zipped, _ = earl("show", "--format", "json", str(CORPUS / "cameo" / "arrowhead-tank-control-md19.mdzip"))
    plain, _ = earl("show", "--format", "json", str(CORPUS / "cameo" / "arrowhead-tank-control-md19-model.xmi"))
    first, second = json.loads(zipped.stdout), json.loads(plain.stdout)
    assert first["file"].endswith("arrowhead-tank-control-md19.mdzip!com.nomagic.magicdraw.uml_model.model")
    assert {k: v for k, v in first.items() if k != "file"} == {k: v for k, v in second.items() if k != "file"}

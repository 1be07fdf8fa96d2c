"""Every file of the shared corpus of real third-party models goes through ``show``, ``check`` and
``stats``: no traceback, the expected dialect, the documented exit codes, in reasonable time.

The corpus (``../shared/corpus`` beside the checkout, see its README) holds no EARL model, so
``check`` reports R003 on every file it can read. The tests are skipped without the corpus.
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
    assert len(findings) == 1 and " R003 error: " in findings[0], checked.stdout
    assert checked.stdout.splitlines()[-1] == "1 file checked: 1 error(s), 0 warning(s), 0 info"


@needs_corpus
def test_an_mdzip_and_its_model_member_give_the_same_model() -> None:
    zipped, _ = earl("show", "--format", "json", str(CORPUS / "cameo" / "arrowhead-tank-control-md19.mdzip"))
    plain, _ = earl("show", "--format", "json", str(CORPUS / "cameo" / "arrowhead-tank-control-md19-model.xmi"))
    first, second = json.loads(zipped.stdout), json.loads(plain.stdout)
    assert first["file"].endswith("arrowhead-tank-control-md19.mdzip!com.nomagic.magicdraw.uml_model.model")
    assert {k: v for k, v in first.items() if k != "file"} == {k: v for k, v in second.items() if k != "file"}

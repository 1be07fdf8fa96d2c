"""`check` finds exactly what it found before: every finding of every sample, fixture, fuzz
regression and corpus file, and of a generated bench model, against tests/golden/findings.json.

Speed work on the reader, the lift and the rules must not change a single finding (code,
severity, line, message, element). After an intended change of findings, rewrite the file with

    .venv/bin/python tests/test_findings_unchanged.py

and review its diff like code.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import pytest

from earl_m2t.api import check
from earl_m2t.deep_stack import call_with_deep_stack
from earl_m2t.diagnostics import ModelReadError

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"
GOLDEN = ROOT / "tests" / "golden" / "findings.json"
MODEL_SUFFIXES = {".uml", ".xmi", ".xml", ".mdzip", ".sysml"}
GENERATED = "bench/generate.py --agents 5 --subsystems 2 --behaviours 5"


# The OMG SysML v2 release (examples and standard library) in the corpus is far beyond the
# subset the SysML v2 reader knows; its findings are not held here (tests/test_corpus.py).
OMG_RELEASE = SHARED / "corpus" / "sysmlv2-omg"


def model_files() -> list[Path]:
    folders = [ROOT / "samples", ROOT / "tests" / "fixtures", ROOT / "tests" / "fuzz" / "regressions",
               SHARED / "corpus"]
    return sorted(path for folder in folders for path in folder.rglob("*")
                  if path.suffix in MODEL_SUFFIXES and path.is_file() and not path.is_relative_to(OMG_RELEASE))


def label(path: Path) -> str:
    """Project files relative to the checkout, the corpus as shared/corpus/…."""
    return (path.relative_to(ROOT) if path.is_relative_to(ROOT) else path.relative_to(ROOT.parent)).as_posix()


def without_checkout(text: str) -> str:
    """Paths in messages as :func:`label` writes them, so that any checkout compares equal."""
    text = text.replace(str(ROOT) + "/", "").replace(str(SHARED.resolve()), "shared")  # ../shared may be a link
    text = text.replace(str(ROOT.parent) + "/", "")
    return text.replace(f"repository ({ROOT.name})", "repository (CHECKOUT)")


def findings_of(path: Path) -> list[str]:
    try:
        found = call_with_deep_stack(lambda: check(path))  # as the command line runs it
    except ModelReadError as error:
        return [without_checkout(f"unreadable: {error}")]
    return [without_checkout(f"{d.location.line}: {d.code} {d.severity.value}: {d.message} [{d.element}]")
            for d in found]


def generated_model(tmp: Path) -> Path:
    spec = importlib.util.spec_from_file_location("bench_generate", ROOT / "bench" / "generate.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = tmp / "generated.uml"
    path.write_bytes(module.generate(agents=5, subsystems=2, behaviours=5))
    return path


def all_findings(tmp: Path) -> dict[str, list[str]]:
    result = {label(path): findings_of(path) for path in model_files()}
    result[GENERATED] = findings_of(generated_model(tmp))
    return result


def test_findings_are_unchanged(tmp_path: Path) -> None:
    if not (SHARED / "corpus").is_dir():
        pytest.fail("../shared/corpus is missing beside the checkout")
    expected = json.loads(GOLDEN.read_text(encoding="utf-8"))
    actual = all_findings(tmp_path)
    assert sorted(actual) == sorted(expected), "the set of model files changed: rewrite the golden file"
    changed = [name for name in expected if actual[name] != expected[name]]
    for name in changed:
        print(f"{name}:\n  expected {expected[name]}\n  actual   {actual[name]}")
    assert not changed, f"findings changed for {len(changed)} file(s): {changed[:5]}"
    assert sum(len(v) for v in actual.values()) > 100  # the golden file holds real findings


if __name__ == "__main__":
    import tempfile

    with tempfile.TemporaryDirectory() as scratch:
        findings = all_findings(Path(scratch))
    GOLDEN.write_text(json.dumps(findings, indent=1, ensure_ascii=False, sort_keys=True) + "\n", encoding="utf-8")
    print(f"{GOLDEN.relative_to(ROOT)}: {len(findings)} models, {sum(len(v) for v in findings.values())} findings",
          file=sys.stderr)

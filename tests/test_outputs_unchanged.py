"""Every output earl-m2t writes for a model is byte-identical to what it wrote before: each
`gen` target, `show` (text and JSON), `convert --to sysml`, the Promela of `verify` and the
`report`, for the samples (all four dialects and the EA variants), every fixture, the fuzz
regressions and a generated bench model, against tests/golden/outputs.json (a SHA-256 per file).

Restructuring the code must not change a byte of what users get. After an intended change of
output, rewrite the file with

    .venv/bin/python tests/test_outputs_unchanged.py

and review the change: `--dump DIR` writes every output under DIR, so that the files of two
commits can be compared with `diff -r`.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import multiprocessing
import os
import shutil
import sys
import tempfile
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest

from earl_m2t.api import Loaded, check_loaded, load
from earl_m2t.check.engine import CheckOptions
from earl_m2t.deep_stack import call_with_deep_stack
from earl_m2t.diagnostics import ModelReadError

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = ROOT / "tests" / "golden" / "outputs.json"
MODEL_SUFFIXES = {".uml", ".xmi", ".xml", ".mdzip", ".sysml"}
FOLDERS = ("samples", "tests/fixtures", "tests/fuzz/regressions")
GEN_TARGETS = ("cpp", "msg", "ros", "ros2", "orocos", "diagrams", "markdown")
SAMPLE = "samples/pick_and_place/pick_and_place.uml"
GENERATED = "bench/generate.py --agents 5 --subsystems 2 --behaviours 5"

Outputs = dict[str, bytes]


def model_labels() -> list[str]:
    return sorted(path.relative_to(ROOT).as_posix() for folder in FOLDERS for path in (ROOT / folder).rglob("*")
                  if path.suffix in MODEL_SUFFIXES and path.is_file())


def copy_sources(scratch: Path) -> Path:
    """The model folders under ``scratch/src``: outputs then name the model by the same relative
    path (from ``scratch/out/…``) in every checkout."""
    source = scratch / "src"
    for folder in FOLDERS:
        shutil.copytree(ROOT / folder, source / folder, symlinks=True)
    return source


def generated_model(source: Path) -> Path:
    import importlib.util

    spec = importlib.util.spec_from_file_location("bench_generate", ROOT / "bench" / "generate.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = source / "bench" / "generated.uml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(module.generate(agents=5, subsystems=2, behaviours=5))
    return path


def _attempt(name: str, outputs: Outputs, make: Callable[[], Outputs | bytes]) -> None:
    """The outputs ``make`` writes, or the one-line error it stops with (as `gen` prints it)."""
    from earl_m2t.gen import GenError
    from earl_m2t.output import OutputError
    from earl_m2t.verify.ltl import LtlError

    try:
        made = call_with_deep_stack(make)
    except (GenError, LtlError, OutputError) as error:
        outputs[f"{name}/ERROR"] = str(error).encode("utf-8")
        return
    if isinstance(made, bytes):
        outputs[name] = made
    else:
        outputs.update({f"{name}/{path}": content for path, content in made.items()})


def _folder(path: Path) -> Outputs:
    return {p.relative_to(path).as_posix(): p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()}


def outputs_of(model_file: Path, out: Path, png: bool) -> Outputs:
    """Every output for one model file, by name."""
    try:
        loaded = call_with_deep_stack(lambda: load(model_file))
    except ModelReadError as error:
        return {"unreadable": str(error).encode("utf-8")}
    outputs: Outputs = {}
    _show_and_convert(loaded, outputs)
    if not loaded.model.systems:
        return outputs
    _verify(loaded, outputs)
    for target in GEN_TARGETS + (("diagrams-png",) if png else ()):
        _attempt(f"gen-{target}", outputs, lambda target=target: _gen(loaded, target, out / target))
    findings = check_loaded(loaded, CheckOptions())
    _attempt("report", outputs, lambda: _report(loaded, findings))
    return outputs


def _show_and_convert(loaded: Loaded, outputs: Outputs) -> None:
    from earl_m2t.convert import to_sysml
    from earl_m2t.export import model_to_dict
    from earl_m2t.render.show_text import render_model

    document = model_to_dict(loaded.model)
    document["ltl_properties"] = [{"name": p.title, "formula": p.text, "file": p.location.file,
                                   "line": p.location.line} for p in loaded.properties]
    outputs["show.json"] = json.dumps(document, indent=2, ensure_ascii=False).encode("utf-8")
    outputs["show.txt"] = render_model(loaded.model).encode("utf-8")
    outputs["convert.sysml"] = to_sysml(loaded.model).encode()


def _verify(loaded: Loaded, outputs: Outputs) -> None:
    from earl_m2t.verify.promela import translate

    def promela() -> Outputs:
        spec = translate(loaded.model, loaded.properties)
        return {"model.pml": spec.text.encode("utf-8"),
                **{f"{name}.ltl": formula.encode("utf-8") for name, formula in sorted(spec.formulas.items())}}

    _attempt("verify", outputs, promela)


def _gen(loaded: Loaded, target: str, folder: Path) -> Outputs:
    from earl_m2t.gen import generate

    report = generate(loaded.model, folder, target, strict=False)
    return {**_folder(folder), "NOTES": "\n".join(report.notes).encode("utf-8")}


def _report(loaded: Loaded, findings: list) -> Outputs:
    from earl_m2t.report.page import render_report

    return dict(render_report(loaded.model, findings))


def normalised(outputs: Outputs, scratch: Path) -> Outputs:
    """Outputs with the scratch folder's absolute path written as ``SCRATCH``."""
    text = str(scratch).encode("utf-8")
    return {name: content.replace(text, b"SCRATCH") for name, content in outputs.items()}


def _normalised_outputs_of(model_file: Path, out: Path, png: bool, scratch: Path) -> Outputs:
    return normalised(outputs_of(model_file, out, png), scratch)


def all_outputs(scratch: Path) -> dict[str, Outputs]:
    """Every output of every model; run in ``scratch`` (the working folder), so that messages
    name the models by the same relative paths, short enough not to be shortened, everywhere.
    The models are independent: one worker process per CPU (forked, so in ``scratch`` too)."""
    assert Path.cwd() == scratch
    copy_sources(scratch)
    source = Path("src")
    models = [(label, source / label) for label in model_labels()] + [(GENERATED, generated_model(source))]
    context = multiprocessing.get_context("fork")
    with ProcessPoolExecutor(max_workers=os.cpu_count() or 1, mp_context=context) as pool:
        futures = {label: pool.submit(_normalised_outputs_of, path, Path("out") / str(number), label == SAMPLE, scratch)
                   for number, (label, path) in enumerate(models)}
        return {label: future.result() for label, future in futures.items()}


def digests(outputs: dict[str, Outputs]) -> dict[str, dict[str, str]]:
    return {label: {name: hashlib.sha256(content).hexdigest() for name, content in sorted(files.items())}
            for label, files in outputs.items()}


def test_outputs_are_unchanged(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    expected = json.loads(GOLDEN.read_text(encoding="utf-8"))
    monkeypatch.chdir(tmp_path)
    actual = digests(all_outputs(tmp_path))
    assert sorted(actual) == sorted(expected), "the set of model files changed: rewrite the golden file"
    changed = {}
    for label, files in expected.items():
        names = sorted(set(files) | set(actual[label]))
        differing = [name for name in names if files.get(name) != actual[label].get(name)]
        if differing:
            changed[label] = differing
    for label, names in changed.items():
        print(f"{label}: {len(names)} output(s) differ: {names[:8]}")
    assert not changed, f"outputs changed for {len(changed)} model(s): {sorted(changed)[:5]}"
    # the golden file holds real outputs: every target of the sample, compiled code among them
    sample = expected[SAMPLE]
    assert all(any(name.startswith(f"gen-{t}/") and not name.endswith("ERROR") for name in sample)
               for t in GEN_TARGETS)
    assert sum(len(files) for files in expected.values()) > 2000


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dump", type=Path, help="write every output under this folder instead")
    args = parser.parse_args()
    dump = args.dump.resolve() if args.dump else None
    with tempfile.TemporaryDirectory() as name:
        os.chdir(name)
        outputs = all_outputs(Path(name))
        os.chdir(ROOT)
    if dump:
        for label, files in outputs.items():
            for output, content in files.items():
                path = dump / label.replace("/", "_") / output
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_bytes(content)
        return 0
    found = digests(outputs)
    GOLDEN.write_text(json.dumps(found, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    print(f"{GOLDEN.relative_to(ROOT)}: {len(found)} models, {sum(len(v) for v in found.values())} outputs",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

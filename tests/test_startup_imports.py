"""Start-up discipline: a command imports only what it uses.

Each command runs in a fresh interpreter (the command line's ``main``, as ``earl-m2t`` runs
it) that then lists the modules it imported. ``--help``, ``--version``, ``rules`` and
``profile`` load no rule, no grammar (textX), no SAT solver (PySAT) and no graph library
(networkx); ``check`` of an XMI model whose profile, invariants and predicate texts are in
the cache loads no grammar. Nothing here is timed.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"

RUN_AND_LIST_MODULES = """
import json, sys
from earl_m2t.cli.app import main
try:
    code = main(sys.argv[2:])
except SystemExit as stop:
    code = stop.code
with open(sys.argv[1], "w", encoding="utf-8") as out:
    json.dump({"code": code, "modules": sorted(sys.modules)}, out)
"""

GRAMMAR = ("textx", "arpeggio")
SOLVER = ("pysat",)
GRAPHS = ("networkx",)
RULES = ("earl_m2t.check.rules", "earl_m2t.check.engine", "earl_m2t.analysis")
READERS = ("lxml", "earl_m2t.read.xmi", "earl_m2t.lift", "earl_m2t.api", "jinja2")


def _env(cache_home: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("EARL_M2T_NO_CACHE", "PYTHONPATH")}
    env["XDG_CACHE_HOME"] = str(cache_home)
    return env


def _modules_after(tmp_path: Path, cache_home: Path, *args: str) -> tuple[int, set[str]]:
    listing = tmp_path / "modules.json"
    result = subprocess.run([sys.executable, "-c", RUN_AND_LIST_MODULES, str(listing), *args], cwd=tmp_path,
                            env=_env(cache_home), capture_output=True, text=True, timeout=300)
    assert listing.is_file(), result.stderr
    data = json.loads(listing.read_text(encoding="utf-8"))
    return data["code"], set(data["modules"])


def _loaded(modules: set[str], families: tuple[str, ...]) -> list[str]:
    return sorted(m for m in modules if any(m == f or m.startswith(f + ".") for f in families))


@pytest.mark.parametrize("args", [("--help",), ("--version",), ("check", "--help"), ("gen", "--help"),
                                  ("rules",), ("rules", "B006"), ("rules", "--format", "json")],
                         ids=lambda args: " ".join(args))
def test_help_version_and_rules_load_no_rule_reader_grammar_solver_or_graph_library(
        tmp_path: Path, args: tuple[str, ...]) -> None:
    code, modules = _modules_after(tmp_path, tmp_path / "cache", *args)
    assert code == 0
    assert "earl_m2t.cli.app" in modules  # the listing is of a process that ran the command line
    assert _loaded(modules, GRAMMAR + SOLVER + GRAPHS + RULES + READERS) == []


def test_profile_loads_no_rule_grammar_solver_or_graph_library_once_the_profile_is_cached(tmp_path: Path) -> None:
    cache_home = tmp_path / "cache"
    first, cold = _modules_after(tmp_path, cache_home, "profile", "--format", "ea", "-o", str(tmp_path / "out"))
    assert first == 0
    assert _loaded(cold, GRAMMAR) != []  # the first run parses profiles/earl.sysml: the probe sees textX
    code, modules = _modules_after(tmp_path, cache_home, "profile", "--format", "ea", "-o", str(tmp_path / "out"))
    assert code == 0
    assert "jinja2" in modules  # it did render
    assert _loaded(modules, GRAMMAR + SOLVER + GRAPHS + RULES) == []


def test_a_second_check_of_a_model_loads_no_grammar(tmp_path: Path) -> None:
    """The profile, the rules' invariants and the model's predicate texts come from the cache."""
    cache_home = tmp_path / "cache"
    first, cold = _modules_after(tmp_path, cache_home, "check", str(SAMPLE))
    assert first == 0
    assert _loaded(cold, GRAMMAR) != []
    assert any(p.name.startswith("predicates-") for p in (cache_home / "earl-m2t").iterdir())
    code, modules = _modules_after(tmp_path, cache_home, "check", str(SAMPLE))
    assert code == 0
    assert "earl_m2t.check.rules.behaviour" in modules  # the rules did run ...
    assert _loaded(modules, GRAMMAR) == []  # ... on trees read from the cache


def test_check_loads_the_grammar_when_the_cache_is_off(tmp_path: Path) -> None:
    listing = tmp_path / "modules.json"
    env = _env(tmp_path / "cache") | {"EARL_M2T_NO_CACHE": "1"}
    for _ in range(2):
        subprocess.run([sys.executable, "-c", RUN_AND_LIST_MODULES, str(listing), "check", str(SAMPLE)],
                       cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300, check=True)
    data = json.loads(listing.read_text(encoding="utf-8"))
    assert data["code"] == 0
    assert _loaded(set(data["modules"]), GRAMMAR) != []
    assert not (tmp_path / "cache" / "earl-m2t").exists()


def test_the_public_api_is_imported_on_first_use_and_check_stays_the_function(tmp_path: Path) -> None:
    """``earl_m2t.check`` is both a subpackage and the public function; importing the
    subpackage first must not hide the function."""
    probe = """
import sys
import earl_m2t
lazy = "earl_m2t.api" not in sys.modules and "earl_m2t.check" not in sys.modules
import earl_m2t.check.engine
from earl_m2t import CheckOptions, Diagnostic, Loaded, ModelReadError, Severity, check, load
import earl_m2t.api as api
from earl_m2t.check import engine
print(lazy, check is api.check, load is api.load, Loaded is api.Loaded, CheckOptions is engine.CheckOptions,
      earl_m2t.check is api.check, sorted(earl_m2t.__all__) == sorted(set(dir(earl_m2t)) & set(earl_m2t.__all__)))
print(len(check(sys.argv[1])))
"""
    result = subprocess.run([sys.executable, "-c", probe, str(SAMPLE)], cwd=tmp_path, env=_env(tmp_path / "cache"),
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split("\n")[:2] == ["True True True True True True True", "0"]


def test_the_choices_named_in_the_command_line_are_those_of_the_implementations() -> None:
    """The parser names output formats, dialects and profile formats without importing what
    implements them; these are the implementations' own lists."""
    from earl_m2t.cli import check, verify
    from earl_m2t.cli.dialect_option import dialect_names
    from earl_m2t.cli.profile_formats import profile_formats
    from earl_m2t.profile_export.formats import FORMATS as PROFILE_FORMATS
    from earl_m2t.read.dialects import dialect_table
    from earl_m2t.render.diagnostics import FORMATS as CHECK_FORMATS
    from earl_m2t.verify.render import RENDERERS
    from earl_m2t.verify.run import CHECK_CODES

    assert tuple(sorted(CHECK_FORMATS)) == check.OUTPUT_FORMATS
    assert tuple(RENDERERS) == verify.OUTPUT_FORMATS
    assert tuple(sorted(CHECK_CODES)) == verify.CHECK_CODES
    assert dialect_names() == dialect_table().names
    assert profile_formats() == PROFILE_FORMATS

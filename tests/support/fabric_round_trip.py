"""FABRIC packages through earl-m2t and back: ``import fabric`` → ``check`` → ``gen --target
orocos`` → FABRIC's own parser on every regenerated spec → the element-by-element comparison
of tests/support/fabric_compare.py with the original.

Also a command for packages outside the repository (the sources of a robot, say):

    PYTHONPATH=. python -m tests.support.fabric_round_trip PACKAGE_DIR... [--each]

prints one line per step and package and exits 1 when any step fails. ``--each`` imports every
package on its own as well as all of them together.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from tests.support import fabric
from tests.support.fabric_compare import differences

ROOT = Path(__file__).resolve().parents[2]


@dataclass
class RoundTrip:
    """What each step said; ``failures`` is empty when all passed."""

    steps: list[str] = field(default_factory=list)
    failures: list[str] = field(default_factory=list)

    def step(self, ok: bool, text: str) -> bool:
        self.steps.append(f"{'ok  ' if ok else 'FAIL'} {text}".rstrip())
        if not ok:
            self.failures.append(text)
        return ok


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)


def regenerated_spec(package: str, out: Path) -> Path:
    """The regenerated spec of an imported package: the one whose subsystem definition (its
    block, named in the spec's heading comment) is the package."""
    for spec in sorted(out.glob("fabric/*/spec/subsystem.xml")):
        if f"({package})" in spec.read_text(encoding="utf-8").partition("-->")[0]:
            return spec
    return out / "fabric" / package / "spec" / "subsystem.xml"


CPP_CONDITION = re.compile(r"(\s|\(|\)|!|&&|\|\||true|false|p->[A-Za-z_][A-Za-z0-9_]*)*")


def unusable_conditions(spec: Any) -> list[str]:
    """The conditions of a parsed spec that FABRIC's logicExprToCpp refuses or turns into
    something other than a C++ Boolean expression over ``p->`` members."""
    to_cpp = fabric.logic_expr_to_cpp()
    found: list[str] = []
    for where, text in fabric.conditions(spec):
        try:
            cpp = to_cpp(text, list(spec.predicates))
        except Exception as exc:  # what FABRIC's code raises
            found.append(f"{where} {text!r}: {exc!r}")
            continue
        if CPP_CONDITION.fullmatch(cpp) is None:
            found.append(f"{where} {text!r} -> {cpp!r}")
    return found


def io_channels(configurations: list[Path], aliases: set[str]) -> dict[str, list[str]]:
    """The IPC channels every spec buffer alias is given by the configurations (one each per
    subsystem instance, that is per configuration)."""
    found: dict[str, set[str]] = {}
    for path in configurations:
        for element in ElementTree.parse(path).getroot().iter("io_buffer"):
            if element.get("alias") in aliases:
                found.setdefault(element.get("alias", ""), set()).add(element.get("name", ""))
    return {alias: sorted(names) for alias, names in sorted(found.items())}


def round_trip(folders: list[Path], work: Path) -> RoundTrip:
    result = RoundTrip()
    model = work / "model.sysml"
    names = " ".join(f.name for f in folders)
    imported = earl("import", "fabric", *map(str, folders), "-o", str(model), "--force")
    if not result.step(imported.returncode == 0, f"import {names}: {imported.stderr.strip()[-400:]}"):
        return result
    checked = earl("check", str(model))
    summary = checked.stdout.strip().splitlines()[-1] if checked.stdout.strip() else checked.stderr.strip()
    errors = [line for line in checked.stdout.splitlines() if " error: " in line]
    result.step(checked.returncode == 0 and " 0 error(s)" in summary, f"check: {summary} {' | '.join(errors[:5])}")
    out = work / "out"
    generated = earl("gen", str(model), "--target", "orocos", "-o", str(out))
    if not result.step(generated.returncode == 0, f"gen --target orocos: {generated.stderr.strip()[-400:]}"):
        return result
    for folder in folders:
        spec = regenerated_spec(folder.name, out)
        try:
            again = fabric.parse_spec(spec)
        except Exception as exc:  # what FABRIC's parser raises, reported as a failed step
            result.step(False, f"{folder.name}: FABRIC's parser refuses {spec}: {exc!r}")
            continue
        result.step(True, f"{folder.name}: FABRIC's parser accepts the regenerated spec")
        refused = unusable_conditions(again)
        result.step(not refused, f"{folder.name}: FABRIC's logicExprToCpp makes C++ of every condition "
                    + "; ".join(refused))
        for config in sorted(spec.parent.parent.glob("config/*.xml")):
            problems = fabric.configuration_problems(config, again)
            result.step(not problems, f"{folder.name}: {config.name} {'; '.join(problems) or 'as runXmls() reads it'}")
        original = fabric.parse_spec(folder / "spec" / "subsystem.xml")
        aliases = {b.alias for b in original.buffers_in + original.buffers_out}
        channels = (io_channels(sorted(folder.glob("config/*.xml")), aliases),
                    io_channels(sorted(spec.parent.parent.glob("config/*.xml")), aliases))
        result.step(channels[0] == channels[1], f"{folder.name}: the configurations' <io_buffer> channels "
                    + ("are the same" if channels[0] == channels[1] else f"differ: {channels[0]} != {channels[1]}"))
        found = differences(original, again)
        result.step(not found, f"{folder.name}: equal element by element" if not found
                    else f"{folder.name}: differs: " + "; ".join(found))
    return result


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("packages", nargs="+", type=Path)
    parser.add_argument("--each", action="store_true", help="also import every package on its own")
    args = parser.parse_args(argv)
    groups = ([[p] for p in args.packages] if args.each else []) + [list(args.packages)]
    failed = False
    for group in groups:
        with tempfile.TemporaryDirectory() as work:
            outcome = round_trip(group, Path(work))
        print(f"== {' '.join(p.name for p in group)}")
        print("\n".join(outcome.steps))
        failed |= bool(outcome.failures)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

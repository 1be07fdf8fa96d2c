"""The import graph of the package, measured from its source: which module imports which
(imports inside functions and ``TYPE_CHECKING`` blocks included), its circles, the imports that
run from a lower layer to a higher one (docs/layers.toml), and the longest modules and
functions. ``python -m tests.support.import_graph`` prints the figures docs/architecture.md
quotes; tests/test_architecture.py holds the code to them.
"""

from __future__ import annotations

import ast
import sys
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from tests.support.paths import ROOT

PACKAGE = "earl_m2t"
LAYERS = ROOT / "docs" / "layers.toml"


@dataclass(frozen=True)
class Module:
    name: str  # earl_m2t.check.engine
    path: Path
    lines: int
    imports: tuple[tuple[str, int], ...]  # (module imported, line)
    functions: tuple[tuple[str, int], ...]  # (qualified name, lines)


def modules(root: Path = ROOT) -> dict[str, Module]:
    found: dict[str, Path] = {}
    for path in sorted((root / PACKAGE).rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return {name: _read(name, path, found) for name, path in found.items()}


def _read(name: str, path: Path, known: dict[str, Path]) -> Module:
    text = path.read_text(encoding="utf-8")
    tree = ast.parse(text, str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    imports: list[tuple[str, int]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            imports.extend((alias.name, node.lineno) for alias in node.names if alias.name in known)
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(node, package)
            for alias in node.names:
                target = f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                if target in known:
                    imports.append((target, node.lineno))
    return Module(name, path, len(text.splitlines()), tuple(dict.fromkeys(imports)), tuple(_functions(tree)))


def _absolute(node: ast.ImportFrom, package: str) -> str:
    if not node.level:
        return node.module or ""
    parts = package.split(".")
    base = parts[: len(parts) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


def _functions(tree: ast.Module) -> Iterator[tuple[str, int]]:
    def visit(node: ast.AST, prefix: str) -> Iterator[tuple[str, int]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                name = f"{prefix}{child.name}"
                yield name, (child.end_lineno or child.lineno) - child.lineno + 1
                yield from visit(child, f"{name}.")
            elif isinstance(child, ast.ClassDef):
                yield from visit(child, f"{prefix}{child.name}.")

    yield from visit(tree, "")


def edges(found: dict[str, Module]) -> set[tuple[str, str]]:
    return {(m.name, target) for m in found.values() for target, _ in m.imports if target != m.name}


def circles(found: dict[str, Module]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan's algorithm)."""
    graph: dict[str, list[str]] = {name: [] for name in found}
    for source, target in sorted(edges(found)):
        graph[source].append(target)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []

    def connect(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for successor in graph[node]:
            if successor not in index:
                connect(successor)
                low[node] = min(low[node], low[successor])
            elif successor in on_stack:
                low[node] = min(low[node], index[successor])
        if low[node] == index[node]:
            group = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    for name in sorted(graph):
        if name not in index:
            connect(name)
    return sorted(groups)


@dataclass(frozen=True)
class Layers:
    order: tuple[tuple[str, tuple[str, ...]], ...]  # (layer, its module prefixes), top layer first
    exceptions: frozenset[tuple[str, str]]  # (importer, imported) allowed to run upwards

    def layer_of(self, module: str) -> int:
        """The position of a module's layer (0 the top); the longest matching prefix decides.
        The package itself (``earl_m2t``, its ``__init__``) names no module but itself."""
        best, position = -1, -1
        for number, (_, prefixes) in enumerate(self.order):
            for prefix in prefixes:
                inside = module.startswith(prefix + ".") and prefix != PACKAGE
                if (module == prefix or inside) and len(prefix) > best:
                    best, position = len(prefix), number
        if position < 0:
            raise KeyError(f"{module} is in no layer of {LAYERS.name}")
        return position


def layers(path: Path = LAYERS) -> Layers:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    order = tuple((row["name"], tuple(row["modules"])) for row in data["layer"])
    exceptions = frozenset((row["importer"], row["imported"]) for row in data.get("upward", []))
    return Layers(order, exceptions)


def upward(found: dict[str, Module], table: Layers) -> list[tuple[str, str]]:
    """Imports from a module to one in a higher layer."""
    return sorted((source, target) for source, target in edges(found)
                  if table.layer_of(source) > table.layer_of(target))


def report(found: dict[str, Module], table: Layers) -> str:
    longest_module = max(found.values(), key=lambda m: m.lines)
    functions = [(lines, f"{m.name}.{name}") for m in found.values() for name, lines in m.functions]
    longest_function = max(functions)
    rows = [
        f"modules: {len(found)}",
        f"imports between modules: {len(edges(found))}",
        f"circles: {len(circles(found))}",
        *(f"  {' <-> '.join(group)}" for group in circles(found)),
        f"imports from a lower layer to a higher one: {len(upward(found, table))}",
        *(f"  {source} -> {target}" for source, target in upward(found, table)),
        f"modules over 450 lines: {sum(1 for m in found.values() if m.lines > 450)}",
        f"longest module: {longest_module.name} ({longest_module.lines} lines)",
        f"functions over 80 lines: {sum(1 for lines, _ in functions if lines > 80)}",
        f"longest function: {longest_function[1]} ({longest_function[0]} lines)",
    ]
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    sys.stdout.write(report(modules(), layers()))

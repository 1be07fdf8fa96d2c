"""The source map of an output folder: ``.earl-trace.json`` beside the generated files.

For every file ``gen`` writes: the model element the file is generated for, and line
ranges ``[first, last, element path]`` for the lines that come from a more specific element
(a transition's guard, a state's row); lines outside the ranges belong to the file's
element. User files (created once, then the user's) and files copied as they are (the
runtime) have no ranges. Each element named is listed once with its kind, XMI id and where
it is written: the model file relative to the output folder, and the line.
The document is written with sorted keys, so it is byte-identical from run to run.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from earl_m2t.element_tree.nodes import Node, model_tree
from earl_m2t.model.elements import EarlModel

TRACE_FILE = ".earl-trace.json"
FORMAT_VERSION = 1


def with_source_map(generated: Mapping[str, bytes], user: Mapping[str, bytes], model: EarlModel,
                    target: str, out_dir: Path | str) -> dict[str, bytes]:
    """``generated`` and the source map of it and of ``user``, ready to be written to ``out_dir``."""
    return {**generated, TRACE_FILE: source_map(generated, user, model, target, Path(out_dir))}


def _elements(model: EarlModel) -> dict[str, Node]:
    found: dict[str, Node] = {}

    def visit(node: Node) -> None:
        if node.path:
            found.setdefault(node.path, node)
        for child in node.children:
            visit(child)

    visit(model_tree(model))
    return found


def _line_ranges(lines: Mapping[int, tuple[str, ...]], file_element: str) -> list[list[Any]]:
    """``[first, last, element]`` for the lines of a more specific element than the file's."""
    chosen: dict[int, str] = {}
    for number, elements in lines.items():
        specific = [e for e in elements if e != file_element]
        if specific:
            chosen[number] = max(reversed(specific), key=len)  # the most nested; the last on ties
    numbers = sorted(chosen)
    for before, after in zip(numbers, numbers[1:]):  # lines between two of the same element are its too
        if chosen[before] == chosen[after]:
            for number in range(before + 1, after):
                chosen[number] = chosen[before]
    ranges: list[list[Any]] = []
    for number in sorted(chosen):
        if ranges and ranges[-1][1] == number - 1 and ranges[-1][2] == chosen[number]:
            ranges[-1][1] = number
        else:
            ranges.append([number, number, chosen[number]])
    return ranges


def source_map(generated: Mapping[str, bytes], user: Mapping[str, bytes], model: EarlModel, target: str,
               out_dir: Path) -> bytes:
    known = _elements(model)
    files: dict[str, Any] = {}
    used: set[str] = set()
    for path, content in sorted({**generated, **user}.items()):
        element = str(getattr(content, "element", "")) if getattr(content, "element", "") in known else ""
        entry: dict[str, Any] = {"element": element or None}
        if path in user:
            entry["user"] = True
        else:
            ranges = [r for r in _line_ranges(getattr(content, "lines", {}), element) if r[2] in known]
            entry["lines"] = ranges
            used.update(r[2] for r in ranges)
        used.add(element)
        files[path] = entry
    root = os.path.abspath(out_dir)
    elements = {path: _element_entry(known[path], root) for path in sorted(used) if path}
    document = {"format": FORMAT_VERSION, "generator": "earl-m2t", "target": target,
                "model": _relative(model.file, root), "elements": elements, "files": files}
    return (json.dumps(document, indent=1, sort_keys=True, ensure_ascii=False) + "\n").encode("utf-8")


def _relative(file: str, root: str) -> str:
    return Path(os.path.relpath(os.path.abspath(file), root)).as_posix() if file else ""


def _element_entry(node: Node, root: str) -> dict[str, Any]:
    location = node.location
    return {"kind": node.kind, "xmi_id": node.xmi_id, "file": _relative(location.file, root), "line": location.line}

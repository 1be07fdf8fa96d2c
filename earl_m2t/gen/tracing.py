"""Which model element each generated line comes from, recorded while templates render.

Views give a dict the element path it stands for under the key ``trace`` (a transition's
row: ``"trace": tr.path``). Templates need not change: the environment hands out the values
of such a dict tagged with that path, and every ``{{ … }}`` that prints a tagged value is
bracketed by invisible markers. After rendering, the markers are removed and give, per
output line, the elements whose values it prints. Dicts and lists inside a traced dict
without a ``trace`` of their own belong to the same element.

The markers are Unicode noncharacters, which never occur in model text; a test renders every
target with and without tracing and compares the bytes.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import jinja2

TRACE_KEY = "trace"
_OPEN, _SEP, _CLOSE = "\ufdd0", "\ufdd1", "\ufdd2"
_MARK = re.compile(f"{_OPEN}([^{_SEP}]*){_SEP}|{_CLOSE}")


class _Traced:
    """A value of a traced dict; ``element`` is the model element path it comes from."""

    element: str


class TracedStr(str, _Traced):
    pass


class TracedInt(int, _Traced):
    pass


class TracedFloat(float, _Traced):
    pass


class TracedDict(dict[Any, Any]):
    """A dict without a ``trace`` of its own, inside a traced one."""

    element: str


class TracedList(list[Any]):
    element: str

    def __iter__(self) -> Iterator[Any]:
        return (_tag(item, self.element) for item in super().__iter__())

    def __getitem__(self, index: Any) -> Any:
        return _tag(super().__getitem__(index), self.element)


def element_of(value: Any) -> str:
    """The element a template value stands for, "" when none."""
    if isinstance(value, dict) and isinstance(value.get(TRACE_KEY), str):
        return str(value[TRACE_KEY])
    return str(getattr(value, "element", "")) if isinstance(value, (_Traced, TracedDict, TracedList)) else ""


def _tag(value: Any, element: str) -> Any:
    if not element or isinstance(value, bool) or value is None:
        return value
    tagged: Any
    if isinstance(value, dict):
        if TRACE_KEY in value or isinstance(value, TracedDict):
            return value
        tagged = TracedDict(value)
    elif isinstance(value, list):
        if isinstance(value, TracedList):
            return value
        tagged = TracedList(value)
    elif isinstance(value, str):
        tagged = TracedStr(value)
    elif isinstance(value, int):
        tagged = TracedInt(value)
    elif isinstance(value, float):
        tagged = TracedFloat(value)
    else:
        return value
    tagged.element = element
    return tagged


class TracingEnvironment(jinja2.Environment):
    """A Jinja environment whose output carries the markers (see the module's doc)."""

    def __init__(self, **options: Any) -> None:
        super().__init__(finalize=_finalize, **options)

    def getitem(self, obj: Any, argument: Any) -> Any:
        return _tag(super().getitem(obj, argument), element_of(obj) if argument != TRACE_KEY else "")

    def getattr(self, obj: Any, attribute: str) -> Any:
        return _tag(super().getattr(obj, attribute), element_of(obj) if attribute != TRACE_KEY else "")


def _finalize(value: Any) -> Any:
    if isinstance(value, _Traced) and value.element:
        return f"{_OPEN}{value.element}{_SEP}{value}{_CLOSE}"
    return value


@dataclass(frozen=True)
class Rendering:
    text: str  # without markers
    lines: dict[int, tuple[str, ...]]  # 1-based line -> elements printed on it, innermost last


def strip_markers(marked: str) -> Rendering:
    """The text without markers, and the elements printed on each line."""
    out: list[str] = []
    lines: dict[int, list[str]] = {}
    open_elements: list[tuple[str, int]] = []  # (element, line where its value started)
    line, position = 1, 0
    for match in _MARK.finditer(marked):
        chunk = marked[position:match.start()]
        out.append(chunk)
        line += chunk.count("\n")
        position = match.end()
        if match.group(0) == _CLOSE:
            element, first = open_elements.pop()
            for number in range(first, line + 1):
                lines.setdefault(number, []).append(element)
        else:
            open_elements.append((match.group(1), line))
    out.append(marked[position:])
    return Rendering("".join(out), {n: tuple(dict.fromkeys(found)) for n, found in sorted(lines.items())})


class TracedBytes(bytes):
    """A rendered file's bytes, with the elements of its lines and of the file as a whole."""

    lines: dict[int, tuple[str, ...]]
    element: str


def traced_bytes(rendering: Rendering, element: str) -> TracedBytes:
    content = TracedBytes(rendering.text.encode("utf-8"))
    content.lines = rendering.lines
    content.element = element
    return content


def file_element(context: dict[str, Any]) -> str:
    """The element a file is rendered for: the last traced value of the template's context
    (``system=…, sub=…`` -> the subsystem)."""
    elements = [element_of(value) for value in context.values()]
    return next((e for e in reversed(elements) if e), "")

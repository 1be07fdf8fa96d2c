"""The other model files a model references (``href="types.uml#id"``), read once each.

After the model file is read, every href of its model content is looked at, except in the
features of ``[references] not_followed`` in ``metamodel/xmi/libraries.toml`` (profile
applications and annotations name profiles and Ecore packages, not model elements) and in
tool extensions and stereotype applications:

* an href into a known library (UML primitive types, SysML value types, profiles, the
  metamodel …) is left to name-based resolution; the library is never opened;
* a relative path (``types.uml``, ``../lib/types.uml``, ``Used Project.mdzip``) is read from
  the directory of the file that holds the href, when it lies (links followed) under the git
  work tree holding the model, else the model's folder, or a folder of ``--allow-outside``, and
  is a regular file within the size limit (:mod:`earl_m2t.read.bounded`); with the same
  hardened parser and the same dialect detection as the model (a file whose tool is not
  recognised is read as the dialect the user named, if any); then its own hrefs are looked at
  the same way. Each file is read once per model, whichever path names it, so references back
  and forth between files end;
* ``platform:``, ``file:``, ``http(s):`` and unknown ``pathmap:`` URIs and absolute paths are
  never opened.

A reference whose resource cannot be read (or is never opened) is one R004 finding per
resource, at its first reference, with the number of references; a reference to an id the
file read does not have is one R004 finding per distinct href. The findings join the model's
reader diagnostics, as do those of the files read (R002 duplicate ids).
"""

from __future__ import annotations

import os
import tomllib
from collections import deque
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from lxml import etree

from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity
from earl_m2t.model.location import Location
from earl_m2t.read.bounded import is_under, roots_for, work_tree
from earl_m2t.read.libraries import classify
from earl_m2t.read.xmi import Element, RawModel
from earl_m2t.read.xmi_index import read_raw_model
from earl_m2t.resources import metamodel_path


@cache
def not_followed() -> frozenset[str]:
    """Features whose hrefs are not model references (``[references]`` of libraries.toml)."""
    data = tomllib.loads(metamodel_path("xmi", "libraries.toml").read_text(encoding="utf-8"))
    return frozenset(data.get("references", {}).get("not_followed", ()))


@dataclass
class _Unresolved:
    """The first reference to something that cannot be resolved, and how many there are."""

    href: str
    model: RawModel
    el: Element  # the element holding the href (a <type href=…/>)
    detail: str
    scope: str  # "resource" (it cannot be read) or "href" (its id is not there)
    count: int = 1


@dataclass
class ResourceSet:
    """The model and the files it references, each read once; answers :class:`Resolver`."""

    main: RawModel
    dialect: str | None = None  # the dialect the user named, for files whose tool is unknown
    roots: tuple[Path, ...] = ()  # the folders referenced files must be under (read.bounded.roots_for)
    # the model of each document root; the folder each model's hrefs are relative to (as shown)
    _by_root: dict[Element, RawModel] = field(default_factory=dict, init=False)
    _dirs: dict[int, str] = field(default_factory=dict, init=False)
    # real path -> the model read from it, or why it cannot be read; (id(model), resource) -> real path
    _files: dict[str, RawModel | str] = field(default_factory=dict, init=False)
    _targets: dict[tuple[int, str], str] = field(default_factory=dict, init=False)
    _problems: dict[tuple[str, str], _Unresolved] = field(default_factory=dict, init=False)

    # -- the Resolver protocol -------------------------------------------------------------
    def model_of(self, el: Element) -> RawModel | None:
        if len(self._dirs) < 2:
            return None  # only the model itself
        return self._by_root.get(el.getroottree().getroot())

    def element(self, raw: RawModel, resource: str, fragment: str) -> Element | None:
        key = self._targets.get((id(raw), resource))
        found = self._files.get(key) if key is not None else None
        return found.by_id.get(fragment) if isinstance(found, RawModel) else None

    # -- reading -----------------------------------------------------------------------------
    def add(self, raw: RawModel, path: Path, shown: str) -> None:
        """Register a model read from ``path``, its locations shown under ``shown``."""
        raw.resolver = self
        for root, _ in raw.documents:
            self._by_root[root] = raw
        self._dirs[id(raw)] = os.path.dirname(shown)
        self._files[_real(path)] = raw

    def follow(self) -> list[Diagnostic]:
        """Read every file the model references, transitively; the R004 findings and those of the files read."""
        found: list[Diagnostic] = []
        queue = deque([self.main])
        while queue:
            model = queue.popleft()
            if model is not self.main:
                found.extend(model.diagnostics)
            for el in _followed_hrefs(model):
                self._look_at(model, el, queue)
        return found + [self._diagnostic(problem) for problem in self._problems.values()]

    def _look_at(self, model: RawModel, el: Element, queue: deque[RawModel]) -> None:
        href = el.get("href") or ""
        resource, _, fragment = href.partition("#")
        if not resource or resource.startswith(model.table.local_resource_prefixes):
            return  # this file's own ids
        named = classify(resource)
        if named.kind == "library":
            return
        if named.kind == "closed":
            self._problem(("resource", resource), href, model, el, f"{resource} is {named.reason}")
            return
        if "\0" in named.path:  # no file can be named so (a %00 in the href)
            self._problem(("resource", resource), href, model, el, f"{resource!r} names no file: a null byte")
            return
        shown = os.path.normpath(os.path.join(self._dirs[id(model)], named.path))
        real = _real(Path(shown))
        self._targets[(id(model), resource)] = real
        if real not in self._files:
            outside = not is_under(Path(real), self.roots)
            self._files[real] = self._outside() if outside else self._read(Path(shown), shown, queue)
        target = self._files[real]
        if isinstance(target, str):
            self._problem(("resource", real), href, model, el, f"cannot read {shown}: {target}")
        elif fragment and fragment not in target.by_id:  # no fragment: the file itself
            self._problem(("href", f"{real}#{fragment}"), href, model, el,
                          f"{shown} has no element with xmi:id '{fragment}'")

    def _outside(self) -> str:
        where = "repository" if work_tree(self.roots[0]) == self.roots[0] else "folder"
        return (f"outside the model's {where} ({self.roots[0]}): not read "
                "(--allow-outside DIR or the configuration's allow-outside reads it)")

    def _read(self, path: Path, shown: str, queue: deque[RawModel]) -> RawModel | str:
        """A referenced file as a model (queued for its own references), or why it cannot be read."""
        try:
            try:
                raw = read_raw_model(path)
            except ModelReadError:
                if self.dialect is None or not path.is_file():
                    raise
                raw = read_raw_model(path, self.dialect)  # a tool not recognised: as the model's
        except ModelReadError as exc:
            where = f" (line {exc.line})" if exc.line else ""
            hint = "; a used project is read from beside the model only" if exc.message == "no such file" and \
                path.suffix.lower() == ".mdzip" else ""
            return f"{exc.message}{where}{hint}"
        except (etree.LxmlError, OSError, ValueError, LookupError, RecursionError) as exc:
            return f"{type(exc).__name__}: {str(exc)[:200]}"
        self.add(raw, path, shown)
        queue.append(raw)
        return raw

    # -- findings ----------------------------------------------------------------------------
    def _problem(self, key: tuple[str, str], href: str, model: RawModel, el: Element, detail: str) -> None:
        known = self._problems.get(key)
        if known is None:
            self._problems[key] = _Unresolved(href, model, el, detail, key[0])
        else:
            known.count += 1

    def _diagnostic(self, problem: _Unresolved) -> Diagnostic:
        model, el = problem.model, problem.el
        owner = el.getparent()
        referring = owner if owner is not None and model.xmi_id(owner) else el
        name = model.name(referring) or model.xmi_id(referring)
        what = f"{model.uml_type(referring) or 'element'} '{name}'"
        feature = el.tag if referring is not el else "href"
        more = f" ({problem.count} references to this {problem.scope})" if problem.count > 1 else ""
        message = f"unresolved reference {problem.href} ({feature} of {what}): {problem.detail}{more}"
        location = Location(model.file_of(el), el.sourceline or 0, 0, model.xmi_id(referring))
        return Diagnostic("R004", Severity.WARNING, message, location, name)


def follow_references(raw: RawModel, path: Path, dialect: str | None = None) -> None:
    """Read the files ``raw`` (read from ``path``) references; findings go to ``raw.diagnostics``."""
    resources = ResourceSet(raw, dialect, roots_for(path))
    resources.add(raw, path, str(path))
    raw.diagnostics.extend(resources.follow())
    if resources.model_of(raw.root) is None:
        raw.resolver = None  # nothing else was read: every element is the model's own


def _followed_hrefs(model: RawModel) -> list[Element]:
    """The elements of a model's content that carry an href into another resource."""
    skipped = not_followed()
    return [el for top, el in model.external_hrefs if _is_followed(el, top, skipped)]


def _is_followed(el: Element, top: Element, skipped: frozenset[str]) -> bool:
    """Model content: not inside a not-followed feature, a tool extension or a stereotype application."""
    if not isinstance(el.tag, str) or el.tag.startswith("{"):
        return False
    for ancestor in el.iterancestors():
        if ancestor is top:
            return True
        tag = ancestor.tag
        if not isinstance(tag, str) or tag.startswith("{") or tag in skipped:
            return False
    return False


def _real(path: Path) -> str:
    """The one key of a file, whichever relative path or link names it."""
    try:
        return str(path.resolve())
    except (OSError, RuntimeError, ValueError):
        return os.path.abspath(path)

"""Stage 1's one pass: an XMI file or ``.mdzip`` project into a :class:`RawModel`.

:func:`read_raw_model` reads the file (or the archive's model members); :func:`index_documents`
checks each document's namespaces, splits its top level into UML models and stereotype
applications, and indexes every element by ``xmi:id`` (skipping tool ``xmi:Extension`` blocks,
whose copies repeat model ids), noting the hrefs that name another resource and the profile
applications. Which tool wrote the file is decided by :mod:`earl_m2t.read.dialects`, from the
tables of ``dialects.toml``; the stereotype applications are read by
:mod:`earl_m2t.read.stereotype_applications`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import chain
from pathlib import Path

from lxml import etree

from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity
from earl_m2t.model.location import Location
from earl_m2t.read.bounded import open_regular
from earl_m2t.read.dialects import DialectTable, detect_dialect, dialect_table, normalise_uri
from earl_m2t.read.early import take_parsed
from earl_m2t.read.mdzip import is_archive, read_model_members
from earl_m2t.read.safe_xml import parse_xml_bytes, parse_xml_stream
from earl_m2t.read.stereotype_applications import earl_profile_uris, stereotype_table
from earl_m2t.read.xmi import Element, RawModel, namespace_of
from earl_m2t.sysml2.files import is_sysml2


def read_raw_model(path: Path, dialect: str | None = None) -> RawModel:
    """Read one XMI file or ``.mdzip`` project, leaving its references into other files unresolved."""
    file = str(path)
    if is_sysml2(path):
        raise ModelReadError(file, "is SysML v2 text, not XMI")
    early = take_parsed(path)  # parsed while the command was importing (earl_m2t.read.early)
    if early is not None:
        return index_tree(early.getroot(), file, dialect)
    with open_regular(path) as stream:  # a regular file within the size limit, or an error
        if is_archive(stream):
            members = read_model_members(stream, file)
            documents = [(parse_xml_bytes(m.data, m.file).getroot(), m.file) for m in members]
            return index_documents(documents, dialect)
        tree = parse_xml_stream(stream, file)
    return index_tree(tree.getroot(), file, dialect)


def index_tree(root: Element, file: str, dialect: str | None = None) -> RawModel:
    """Build the id index and the stereotype table in one pass over the tree."""
    return index_documents([(root, file)], dialect)


@dataclass
class _Document:
    root: Element
    file: str
    xmi_ns: str
    uml_ns: str
    model_roots: list[Element]
    applications: list[Element]  # root-level elements of other namespaces: stereotype applications


def index_documents(documents: Sequence[tuple[Element, str]], dialect: str | None = None) -> RawModel:
    """Index one model held in one or more documents (the first is the main one).

    ``dialect`` overrides detection; detection looks at the first document only.
    """
    table = dialect_table()
    docs = [_document(root, file, table) for root, file in documents]
    main = docs[0]
    model_roots = [top for doc in docs for top in doc.model_roots]
    if not model_roots:
        raise ModelReadError(main.file, "XMI file holds no UML model element", main.root.sourceline or 0)
    if dialect is None:
        dialect = detect_dialect(main.root, main.uml_ns, main.xmi_ns, _sample_ids(model_roots[0], main.xmi_ns))
        if dialect not in table.titles:
            known = table.dialect(dialect)
            message = known.message if known is not None and known.message else f"{dialect} XMI is not supported"
            raise ModelReadError(main.file, message, main.root.sourceline or 0)
    elif dialect not in table.titles:
        raise ModelReadError(main.file, f"unknown dialect '{dialect}' (known: {', '.join(table.names)})")

    by_id: dict[str, Element] = {}
    diagnostics: list[Diagnostic] = []
    profile_applications: list[Element] = []
    ext_tags = frozenset(f"{{{uri}}}Extension" for uri in _spellings(table.xmi_uris))
    external_hrefs: list[tuple[Element, Element]] = []
    for doc in docs:
        id_attr = f"{{{doc.xmi_ns}}}id"
        for top in doc.model_roots:
            _index_subtree(top, id_attr, ext_tags, by_id, profile_applications, external_hrefs, diagnostics,
                           doc.file)
    raw = RawModel(main.file, main.root, dialect, main.xmi_ns, main.uml_ns, by_id, {}, model_roots, diagnostics,
                   table, tuple((d.root, d.file) for d in docs), external_hrefs=external_hrefs)
    raw.earl_uris = earl_profile_uris(raw, profile_applications)
    raw.stereotypes = stereotype_table(raw, chain.from_iterable(doc.applications for doc in docs))
    return raw


def _sample_ids(model: Element, xmi_ns: str) -> tuple[str, ...]:
    """The ids of a model root and of its first packaged element, for detection by id shape."""
    id_attr = f"{{{xmi_ns}}}id"
    first = next(model.iterchildren("packagedElement"), None)
    return (model.get(id_attr) or "", first.get(id_attr) or "" if first is not None else "")


def _document(root: Element, file: str, table: DialectTable) -> _Document:
    """Check one document's namespaces and split its top level into models and stereotype applications."""
    nsmap = {uri: prefix for prefix, uri in (root.nsmap or {}).items() if uri}
    xmi_ns = next((uri for uri in nsmap if normalise_uri(uri) in table.xmi_uris), "")
    uml_ns = next((uri for uri in nsmap if table.is_uml(uri)), "")
    root_uri = namespace_of(root)
    if any(normalise_uri(root_uri).startswith(normalise_uri(p)) for p in table.sysml_v2_prefixes):
        raise ModelReadError(file, "SysML v2 XMI (.sysmlx) is not supported", root.sourceline or 0)
    if not xmi_ns:
        raise ModelReadError(
            file, f"not an XMI file (root element <{etree.QName(root).localname}> has no XMI namespace)",
            root.sourceline or 0,
        )
    if not uml_ns:
        raise ModelReadError(file, "XMI file without a UML model (no UML namespace declared)", root.sourceline or 0)
    model_roots: list[Element] = []
    applications: list[Element] = []
    top_level = [root] if root_uri == uml_ns else [c for c in root if isinstance(c.tag, str)]
    kind_of_tag: dict[str, str] = {}  # a file has thousands of applications of a few stereotypes
    for top in top_level:
        kind = kind_of_tag.get(top.tag)
        if kind is None:
            top_uri = namespace_of(top)
            if normalise_uri(top_uri) in table.xmi_uris:
                kind = "xmi"  # xmi:Documentation, and every root-level xmi:Extension (tool data, repeated ids)
            else:
                kind = "model" if top_uri == uml_ns else "application"
            kind_of_tag[top.tag] = kind
        if kind == "model":
            model_roots.append(top)
        elif kind == "application":
            applications.append(top)
    for model in model_roots:  # Enterprise Architect "XMI 2.1" writes them inside the uml:Model
        for child in model:
            uri = namespace_of(child)
            if uri and uri != uml_ns and normalise_uri(uri) not in table.xmi_uris:
                applications.append(child)
    return _Document(root, file, xmi_ns, uml_ns, model_roots, applications)


def _spellings(uris: frozenset[str]) -> set[str]:
    """The spellings a normalised namespace URI may have in a file (http/https, trailing '/')."""
    found: set[str] = set()
    for uri in uris:
        for variant in (uri, "https://" + uri.removeprefix("http://")):
            found.update((variant, variant + "/"))
    return found


def _index_subtree(
    top: Element,
    id_attr: str,
    ext_tags: frozenset[str],
    by_id: dict[str, Element],
    profile_applications: list[Element],
    external_hrefs: list[tuple[Element, Element]],
    diagnostics: list[Diagnostic],
    file: str,
) -> None:
    """One pass over a model root: the id index, the profile applications, and the elements
    whose href leaves the file (references to other resources, followed later)."""
    iterator = top.iter()
    for el in iterator:
        tag = el.tag
        if tag in ext_tags:
            # skip the tool's extension block entirely: its copies repeat model ids
            for _ in el.iterdescendants():
                next(iterator, None)
            continue
        href = el.get("href")
        if href and href[0] != "#":
            external_hrefs.append((top, el))
        ref_id = el.get(id_attr)
        if ref_id is None:
            continue
        if tag == "profileApplication":
            profile_applications.append(el)
        if ref_id in by_id:
            diagnostics.append(
                Diagnostic(
                    "R002",
                    Severity.WARNING,
                    f"duplicate xmi:id '{ref_id}' on <{el.tag}> '{el.get('name') or ''}' "
                    f"(first used on line {by_id[ref_id].sourceline})",
                    Location(file, el.sourceline or 0, 0, ref_id),
                    el.get("name") or ref_id,
                )
            )
            continue
        by_id[ref_id] = el


"""What a tool keeps about model elements in its own ``xmi:Extension``: ``[extension]`` of dialects.toml.

Enterprise Architect exports, beside the UML content, one record per element and per connector
in a root-level ``<xmi:Extension extender="Enterprise Architect">`` (``elements/element``,
``connectors/connector``, each naming its element by ``xmi:idref``). Some of what EA's dialogs
show is only there: an element's Language (``<code gentype="C++"/>``), which the UML part never
gives an opaque behaviour's ``body="…"``, and the number EA handed out when it created a
connector (``<model ea_localid="42"/>``), the only order it keeps for transitions and connectors.

:class:`ExtensionIndex` reads those records in one pass, only the properties the table names;
files of other tools have no such extension and give an empty index.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TypeAlias

from lxml import etree

from earl_m2t.read.dialects import DialectTable, normalise_uri

Element: TypeAlias = etree._Element

__all__ = ["ExtensionIndex", "in_connector_order"]


class ExtensionIndex:
    """The ``[extension]`` properties of each element a tool's extension records describe."""

    def __init__(self, values: dict[str, dict[str, str]]) -> None:
        self._values = values  # element id -> property name -> value

    @classmethod
    def read(cls, roots: Iterable[Element], xmi_ns: str, table: DialectTable) -> ExtensionIndex:
        """Index the records of every root-level ``xmi:Extension`` whose extender the table names."""
        values: dict[str, dict[str, str]] = {}
        if not (table.extension_extenders and table.extension_records and table.extension_properties):
            return cls(values)
        idref = f"{{{xmi_ns}}}idref"
        for root in roots:
            for ext in root:
                if not _is_tool_extension(ext, table):
                    continue
                for path in table.extension_records:
                    for record in ext.iterfind(path):
                        element_id = record.get(idref)
                        if not element_id or element_id in values:
                            continue
                        found = {}
                        for name, (child, attribute) in table.extension_properties.items():
                            holder = record.find(child)
                            value = (holder.get(attribute) or "").strip() if holder is not None else ""
                            if value and value not in table.extension_unset:
                                found[name] = value
                        values[element_id] = found
        return cls(values)

    def get(self, element_id: str, name: str) -> str:
        """The property ``name`` of the element with id ``element_id``; "" when the tool does not say."""
        return self._values.get(element_id, {}).get(name, "")

    def __len__(self) -> int:
        return len(self._values)


def _is_tool_extension(el: Element, table: DialectTable) -> bool:
    tag = el.tag
    if not isinstance(tag, str) or not tag.startswith("{"):
        return False
    uri, _, local = tag[1:].partition("}")
    if local != "Extension" or normalise_uri(uri) not in table.xmi_uris:
        return False
    extender = el.get("extender") or ""
    return any(extender.startswith(name) for name in table.extension_extenders)


def in_connector_order(elements: Sequence[Element], number: Sequence[str]) -> list[Element]:
    """``elements`` ordered by ``number`` (their ``[extension.uses] connector_order`` values), when
    every one has a whole number; otherwise as given."""
    keys: list[int] = []
    for value in number:
        if not value.isdigit():
            return list(elements)
        keys.append(int(value))
    return [el for _, _, el in sorted(zip(keys, range(len(keys)), elements), key=lambda item: item[:2])]

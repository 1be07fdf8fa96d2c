"""The floor of ``bench/run.py``: parse a model and visit every element once from Python.

    python bench/one_pass.py FILE

It parses with the options of the baseline (and of earl-m2t), then makes the one pass any
checker written in Python over lxml makes at the least: every element's ``xmi:id``, and for an
element that has one its ``xmi:type``, name and line kept in an index. It leaves as
``earl-m2t`` does, without freeing the tree (``os._exit``). What ``check`` costs beyond this is
the reading of the model, the lift and the rules.
"""

from __future__ import annotations

import os
import sys

from lxml import etree

XMI_NAMESPACES = ("http://www.omg.org/spec/XMI/20131001", "http://www.omg.org/spec/XMI/20110701",
                  "http://schema.omg.org/spec/XMI/2.1")


def main() -> None:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, dtd_validation=False,
                             huge_tree=True, remove_comments=True, remove_pis=True, collect_ids=False)
    root = etree.parse(sys.argv[1], parser).getroot()
    xmi = next((uri for uri in (root.nsmap or {}).values() if uri in XMI_NAMESPACES), XMI_NAMESPACES[0])
    id_attr, type_attr = f"{{{xmi}}}id", f"{{{xmi}}}type"
    index: dict[str, tuple[etree._Element, str | None, str | None, int | None]] = {}
    for el in root.iter():
        key = el.get(id_attr)
        if key is not None:
            index[key] = (el, el.get(type_attr), el.get("name"), el.sourceline)
    sys.stdout.write(f"{len(index)} elements with an id\n")
    sys.stdout.flush()
    os._exit(0)


if __name__ == "__main__":
    main()

"""The tree ``earl-m2t diff`` compares: the model's elements (:mod:`earl_m2t.element_tree`) and
its LTL properties, the last children of the root."""

from __future__ import annotations

import dataclasses

from earl_m2t.element_tree.nodes import Node, model_tree
from earl_m2t.element_tree.presentation import presentation
from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import EarlModel


def diff_tree(model: EarlModel) -> Node:
    """The model as a tree, with its LTL properties as children of its root."""
    root = model_tree(model)
    if not model.properties:
        return root
    return dataclasses.replace(root, children=root.children + tuple(_property_node(p) for p in model.properties))


def _property_node(prop: LtlProperty) -> Node:
    """An LTL property, matched by the name the model gives it; its formula is compared."""
    cls = type(prop).__name__
    return Node(cls, presentation().kinds.get(cls, cls), prop.title, prop.title, prop.location.xmi_id, prop.location,
                (("formula", prop.text),), ())

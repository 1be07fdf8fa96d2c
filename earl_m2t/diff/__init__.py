"""``earl-m2t diff``: what changed between two models, in EARL terms, read from the lifted models."""

from earl_m2t.diff.compare import Change, FieldChange, compare
from earl_m2t.diff.tree import diff_tree
from earl_m2t.model.elements import EarlModel

__all__ = ["Change", "FieldChange", "compare", "diff_models"]


def diff_models(old: EarlModel, new: EarlModel) -> list[Change]:
    """The changes from ``old`` to ``new``; empty when they are the same EARL model."""
    return compare(diff_tree(old), diff_tree(new))

"""The Python rule implementations, one module per rule family; importing this package
registers every one of them (:func:`earl_m2t.check.rule.rule`)."""

from __future__ import annotations

from earl_m2t.check.rule import RuleFunction, registered_rules
from earl_m2t.check.rules import (  # noqa: F401
    activation,
    behaviour,
    connection,
    datatype,
    groups,
    switching,
    transition,
    unique,
    variability,
)


def python_rules() -> dict[str, RuleFunction]:
    """Every Python rule implementation, by catalogue code."""
    return registered_rules()

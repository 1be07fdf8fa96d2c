"""The EARL predicate language: initial, terminal and error conditions, primitive predicates.

``parse_predicate`` is imported on first use (PEP 562): the grammar (textX) is loaded only
when a text is parsed.

>>> from earl_m2t.predicate import parse_predicate, format_predicate
>>> format_predicate(parse_predicate("newJointPos/pp.fun and not emergencyStop/pp.fun"))
'newJointPos/pp ∧ ¬emergencyStop/pp'
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from earl_m2t.predicate.ast import (
    COMPARISON_OPERATORS,
    FIELD_SUFFIXES,
    And,
    BuiltIn,
    BuiltInPredicate,
    Compare,
    Const,
    Expr,
    FieldRef,
    NewData,
    Node,
    Not,
    Number,
    Operand,
    Or,
    PredicateRef,
    Replicated,
)
from earl_m2t.predicate.errors import PredicateSyntaxError
from earl_m2t.predicate.printer import format_predicate
from earl_m2t.predicate.transform import (
    expand_replicated,
    index_name,
    is_indexed,
    join,
    map_children,
    substitute_index,
)
from earl_m2t.predicate.walk import evaluate, evaluate_atoms, references, walk

if TYPE_CHECKING:
    from earl_m2t.predicate.parser import parse_predicate

__all__ = [
    "COMPARISON_OPERATORS",
    "FIELD_SUFFIXES",
    "And",
    "BuiltIn",
    "BuiltInPredicate",
    "Compare",
    "Const",
    "Expr",
    "FieldRef",
    "NewData",
    "Node",
    "Not",
    "Number",
    "Operand",
    "Or",
    "PredicateRef",
    "PredicateSyntaxError",
    "Replicated",
    "evaluate",
    "evaluate_atoms",
    "expand_replicated",
    "format_predicate",
    "index_name",
    "is_indexed",
    "join",
    "map_children",
    "parse_predicate",
    "references",
    "substitute_index",
    "walk",
]


def __getattr__(name: str) -> Any:
    if name != "parse_predicate":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from earl_m2t.predicate import parser

    globals()[name] = parser.parse_predicate
    return parser.parse_predicate


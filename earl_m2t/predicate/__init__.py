"""The EARL predicate language: initial, terminal and error conditions, primitive predicates.

>>> from earl_m2t.predicate import parse_predicate, format_predicate
>>> format_predicate(parse_predicate("newJointPos/pp.fun and not emergencyStop/pp.fun"))
'newJointPos/pp ∧ ¬emergencyStop/pp'
"""

from earl_m2t.predicate.ast import (
    COMPARISON_OPERATORS,
    FIELD_SUFFIXES,
    And,
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
    split_name,
)
from earl_m2t.predicate.errors import PredicateSyntaxError
from earl_m2t.predicate.parser import parse_predicate
from earl_m2t.predicate.printer import format_predicate
from earl_m2t.predicate.transform import (
    expand_replicated,
    index_name,
    is_indexed,
    join,
    substitute_index,
)
from earl_m2t.predicate.walk import evaluate, evaluate_atoms, references, walk

__all__ = [
    "COMPARISON_OPERATORS",
    "FIELD_SUFFIXES",
    "And",
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
    "parse_predicate",
    "references",
    "split_name",
    "substitute_index",
    "walk",
]

"""What OCL's named operations and operators do to values, as tables by name.

:data:`METHODS` are the operations on single values (``value.name(arguments)``),
:data:`COLLECTION_OPERATIONS` those on collections (``value->name(arguments)``) and
:data:`BINARY` the operators other than the Boolean ones. Each checks the types of its
operands; the compiler (:mod:`earl_m2t.ocl.evaluator`) applies them.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from functools import lru_cache
from typing import Any

from earl_m2t.ocl.errors import OclEvaluationError
from earl_m2t.ocl.values import OclSet, as_collection, equal, is_number, number, string, type_name, unique

# ---- operations on single values: ``value.name(arguments)``


@lru_cache(maxsize=512)
def _regex(pattern: str) -> re.Pattern[str]:
    try:
        return re.compile(pattern)
    except re.error as error:
        raise OclEvaluationError(f"invalid regular expression {pattern!r}: {error}") from None


def _method_matches(value: object, pattern: object) -> bool:
    text = string(value, "matches()")
    return _regex(string(pattern, "matches()")).fullmatch(text) is not None


def _method_starts_with(value: object, prefix: object) -> bool:
    return string(value, "startsWith()").startswith(string(prefix, "startsWith()"))


def _method_ends_with(value: object, suffix: object) -> bool:
    return string(value, "endsWith()").endswith(string(suffix, "endsWith()"))


def _method_concat(value: object, other: object) -> str:
    return string(value, "concat()") + string(other, "concat()")


METHODS: dict[str, Callable[..., object]] = {
    "matches": _method_matches,
    "startsWith": _method_starts_with,
    "endsWith": _method_ends_with,
    "concat": _method_concat,
    "toLower": lambda value: string(value, "toLower()").lower(),
    "toUpper": lambda value: string(value, "toUpper()").upper(),
    "size": lambda value: len(string(value, "size()")),
}


# ---- operations on collections: ``value->name(arguments)``


def _sum(items: Iterable[Any]) -> int | float:
    total: int | float = 0
    for item in items:
        total += number(item, "sum()")
    return total


def _extreme(items: Iterable[Any], pick: Callable[..., Any], what: str) -> object:
    values = list(items)
    if not values:
        return None
    if all(is_number(v) for v in values) or all(isinstance(v, str) for v in values):
        return pick(values)
    raise OclEvaluationError(f"{what} expects numbers or strings")


def _includes(items: Any, value: object) -> bool:
    return any(equal(item, value) for item in items)


COLLECTION_OPERATIONS: dict[str, Callable[..., object]] = {
    "notEmpty": lambda items: len(items) > 0,
    "isEmpty": lambda items: len(items) == 0,
    "size": len,
    "includes": _includes,
    "excludes": lambda items, value: not _includes(items, value),
    "includesAll": lambda items, other: all(_includes(items, v) for v in as_collection(other)),
    "excludesAll": lambda items, other: not any(
        _includes(items, v) for v in as_collection(other)
    ),
    "count": lambda items, value: sum(1 for item in items if equal(item, value)),
    "sum": _sum,
    "min": lambda items: _extreme(items, min, "min()"),
    "max": lambda items: _extreme(items, max, "max()"),
    "first": lambda items: next(iter(items), None),
    "last": lambda items: tuple(items)[-1] if len(items) else None,
    "asSet": lambda items: OclSet(unique(items)),
    "asSequence": tuple,
    "union": lambda items, other: tuple(items) + tuple(as_collection(other)),
}


# ---- operators other than the Boolean ones


def _order(operator: str) -> Callable[[Any, Any], bool]:
    compare: Callable[[Any, Any], bool] = {
        "<": lambda a, b: a < b,
        ">": lambda a, b: a > b,
        "<=": lambda a, b: a <= b,
        ">=": lambda a, b: a >= b,
    }[operator]

    def run(a: Any, b: Any) -> bool:
        if (is_number(a) and is_number(b)) or (isinstance(a, str) and isinstance(b, str)):
            return compare(a, b)
        raise OclEvaluationError(
            f"'{operator}' cannot compare {type_name(a)} with {type_name(b)}"
        )

    return run


def _add(a: Any, b: Any) -> Any:
    if (is_number(a) and is_number(b)) or (isinstance(a, str) and isinstance(b, str)):
        return a + b
    raise OclEvaluationError(f"'+' cannot add {type_name(a)} and {type_name(b)}")


def _divide(a: Any, b: Any) -> Any:
    a, b = number(a, "'/'"), number(b, "'/'")
    if b == 0:
        raise OclEvaluationError("division by zero")
    return a / b


BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "=": equal,
    "<>": lambda a, b: not equal(a, b),
    "<": _order("<"),
    ">": _order(">"),
    "<=": _order("<="),
    ">=": _order(">="),
    "+": _add,
    "-": lambda a, b: number(a, "'-'") - number(b, "'-'"),
    "*": lambda a, b: number(a, "'*'") * number(b, "'*'"),
    "/": _divide,
}

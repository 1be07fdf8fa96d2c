"""The values OCL expressions compute with, and the environment compiled expressions read.

Collections are tuples, lists, sets and frozensets (:data:`COLLECTION_TYPES`); ``asSet()``
gives an :class:`OclSet`, whose equality ignores order. The helpers here check a value's type
for an operation (raising :class:`OclEvaluationError` with the operation's name), compare
values as OCL does (:func:`equal`), and navigate an attribute, collecting over collections.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

from earl_m2t.ocl.errors import OclEvaluationError

Env = dict[str, Any]  # variable name -> value, ``self`` included
Fn = Callable[[Env], Any]  # a compiled expression

COLLECTION_TYPES = (tuple, list, set, frozenset)
UNBOUND = object()  # what a binding saves for a variable the environment did not hold


class OclSet(tuple):
    """A tuple without duplicates whose equality ignores order (the result of ``asSet()``)."""

    __slots__ = ()


def type_name(value: object) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "Boolean"
    if isinstance(value, int):
        return "Integer"
    if isinstance(value, float):
        return "Real"
    if isinstance(value, str):
        return "String"
    if isinstance(value, COLLECTION_TYPES):
        return "Collection"
    return type(value).__name__


def as_collection(value: object) -> tuple[Any, ...] | list[Any] | set[Any] | frozenset[Any]:
    if isinstance(value, COLLECTION_TYPES):
        return value
    if value is None:
        return ()
    return (value,)


def is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def unique(values: Iterable[Any]) -> list[Any]:
    result: list[Any] = []
    seen: set[Any] = set()
    for value in values:
        try:
            if value in seen:
                continue
            seen.add(value)
        except TypeError:  # unhashable: fall back to equality
            if any(equal(value, other) for other in result):
                continue
        result.append(value)
    return result


def equal(left: object, right: object) -> bool:
    if left is right:
        return True
    if isinstance(left, COLLECTION_TYPES) and isinstance(right, COLLECTION_TYPES):
        unordered = (OclSet, set, frozenset)
        if isinstance(left, unordered) or isinstance(right, unordered):
            a, b = unique(left), unique(right)
            return len(a) == len(b) and all(any(equal(x, y) for y in b) for x in a)
        return len(left) == len(right) and all(equal(x, y) for x, y in zip(left, right))
    return bool(left == right)


def boolean(value: object, what: str) -> bool:
    if value is True or value is False:
        return value
    raise OclEvaluationError(f"{what} expects a Boolean, got {type_name(value)} ({value!r})")


def string(value: object, what: str) -> str:
    if isinstance(value, str):
        return value
    raise OclEvaluationError(f"{what} expects a String, got {type_name(value)} ({value!r})")


def number(value: object, what: str) -> int | float:
    if is_number(value):
        return value  # type: ignore[return-value]
    raise OclEvaluationError(f"{what} expects a number, got {type_name(value)} ({value!r})")


def attribute(obj: object, name: str) -> object:
    try:
        return getattr(obj, name)
    except AttributeError:
        raise OclEvaluationError(
            f"{type_name(obj)} has no attribute '{name}'"
        ) from None


def navigate(value: object, name: str) -> object:
    if isinstance(value, COLLECTION_TYPES):
        result: list[Any] = []
        for element in value:
            if element is None:
                continue
            target = attribute(element, name)
            if isinstance(target, COLLECTION_TYPES):
                result.extend(x for x in target if x is not None)
            elif target is not None:
                result.append(target)
        return tuple(result)
    if value is None:
        return None
    return attribute(value, name)

"""Evaluation of OCL expressions over plain Python objects.

An expression tree is compiled once into nested Python closures; each closure takes the
environment (a dict from variable name to value, ``self`` included) and returns a value.
Iterators and ``let`` bind their variable in that dict and restore it afterwards.

Value model:

* attribute navigation is ``getattr``; a missing attribute is an :class:`OclEvaluationError`;
  navigating from ``null`` gives ``null``;
* collections are tuples, lists, sets and frozensets; every collection result is a tuple;
  navigation on a collection navigates each element and flattens the result (implicit
  collect), dropping ``null`` values; ``->`` on a single value sees a one-element collection,
  on ``null`` an empty one;
* ``asSet()`` returns a tuple without duplicates that compares equal to any collection with
  the same elements (in any order); other sequences compare element by element;
* boolean operators, ``if`` conditions and iterator predicates require ``true`` or ``false``;
  ``and``, ``or`` and ``implies`` do not evaluate their right side when the left side decides.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import earl_m2t.ocl.ast as ast
from earl_m2t.ocl.errors import OclEvaluationError

Env = dict[str, Any]
Fn = Callable[[Env], Any]

COLLECTION_TYPES = (tuple, list, set, frozenset)
_MISSING = object()


class OclSet(tuple):
    """A tuple without duplicates whose equality ignores order (the result of ``asSet()``)."""

    __slots__ = ()


@dataclass(frozen=True)
class CompiledExpression:
    """An expression tree together with its compiled form; ``root`` is the syntax tree."""

    root: ast.Node
    function: Fn = field(compare=False, repr=False)

    def __reduce__(self) -> tuple[Callable[[ast.Node], CompiledExpression], tuple[ast.Node]]:
        # closures do not pickle: a cached expression is compiled again from its tree
        return (compile_expression, (self.root,))


def compile_expression(root: ast.Node) -> CompiledExpression:
    return CompiledExpression(root, _compile(root))


def evaluate(
    expression: CompiledExpression | ast.Node,
    self_obj: object,
    variables: dict[str, object] | None = None,
) -> object:
    """Evaluate ``expression`` with ``self`` bound to ``self_obj`` and the given variables."""
    if isinstance(expression, CompiledExpression):
        function = expression.function
    elif isinstance(expression, ast.Node):
        function = _compile(expression)
    else:
        raise TypeError(f"not an OCL expression: {expression!r}")
    env: Env = dict(variables) if variables else {}
    env["self"] = self_obj
    return function(env)


# ---------------------------------------------------------------------------- value helpers


def _type_name(value: object) -> str:
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


def _as_collection(value: object) -> tuple[Any, ...] | list[Any] | set[Any] | frozenset[Any]:
    if isinstance(value, COLLECTION_TYPES):
        return value
    if value is None:
        return ()
    return (value,)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _unique(values: Iterable[Any]) -> list[Any]:
    result: list[Any] = []
    seen: set[Any] = set()
    for value in values:
        try:
            if value in seen:
                continue
            seen.add(value)
        except TypeError:  # unhashable: fall back to equality
            if any(_equal(value, other) for other in result):
                continue
        result.append(value)
    return result


def _equal(left: object, right: object) -> bool:
    if left is right:
        return True
    if isinstance(left, COLLECTION_TYPES) and isinstance(right, COLLECTION_TYPES):
        unordered = (OclSet, set, frozenset)
        if isinstance(left, unordered) or isinstance(right, unordered):
            a, b = _unique(left), _unique(right)
            return len(a) == len(b) and all(any(_equal(x, y) for y in b) for x in a)
        return len(left) == len(right) and all(_equal(x, y) for x, y in zip(left, right))
    return bool(left == right)


def _boolean(value: object, what: str) -> bool:
    if value is True or value is False:
        return value
    raise OclEvaluationError(f"{what} expects a Boolean, got {_type_name(value)} ({value!r})")


def _string(value: object, what: str) -> str:
    if isinstance(value, str):
        return value
    raise OclEvaluationError(f"{what} expects a String, got {_type_name(value)} ({value!r})")


def _number(value: object, what: str) -> int | float:
    if _is_number(value):
        return value  # type: ignore[return-value]
    raise OclEvaluationError(f"{what} expects a number, got {_type_name(value)} ({value!r})")


@lru_cache(maxsize=512)
def _regex(pattern: str) -> re.Pattern[str]:
    try:
        return re.compile(pattern)
    except re.error as error:
        raise OclEvaluationError(f"invalid regular expression {pattern!r}: {error}") from None


def _get(obj: object, name: str) -> object:
    try:
        return getattr(obj, name)
    except AttributeError:
        raise OclEvaluationError(
            f"{_type_name(obj)} has no attribute '{name}'"
        ) from None


def _navigate(value: object, name: str) -> object:
    if isinstance(value, COLLECTION_TYPES):
        result: list[Any] = []
        for element in value:
            if element is None:
                continue
            target = _get(element, name)
            if isinstance(target, COLLECTION_TYPES):
                result.extend(x for x in target if x is not None)
            elif target is not None:
                result.append(target)
        return tuple(result)
    if value is None:
        return None
    return _get(value, name)


# ---------------------------------------------------------------------------- compilation


def _compile(node: ast.Node) -> Fn:
    compiler = _COMPILERS.get(type(node))
    if compiler is None:
        raise TypeError(f"unknown OCL node {type(node).__name__}")
    return compiler(node)


def _compile_literal(node: ast.Literal) -> Fn:
    value = node.value
    return lambda env: value


def _compile_variable(node: ast.Variable) -> Fn:
    name = node.name

    def run(env: Env) -> object:
        try:
            return env[name]
        except KeyError:
            raise OclEvaluationError(f"unknown variable '{name}'") from None

    return run


def _compile_navigation(node: ast.Navigation) -> Fn:
    source, name = _compile(node.source), node.name
    collections = COLLECTION_TYPES

    def run(env: Env) -> object:
        value = source(env)
        if value is None or isinstance(value, collections):
            return _navigate(value, name)
        try:
            return getattr(value, name)
        except AttributeError:
            return _get(value, name)  # raises the located error

    return run


# ---- operations on single values: ``value.name(arguments)``


def _method_matches(value: object, pattern: object) -> bool:
    text = _string(value, "matches()")
    return _regex(_string(pattern, "matches()")).fullmatch(text) is not None


def _method_starts_with(value: object, prefix: object) -> bool:
    return _string(value, "startsWith()").startswith(_string(prefix, "startsWith()"))


def _method_ends_with(value: object, suffix: object) -> bool:
    return _string(value, "endsWith()").endswith(_string(suffix, "endsWith()"))


def _method_concat(value: object, other: object) -> str:
    return _string(value, "concat()") + _string(other, "concat()")


_METHODS: dict[str, Callable[..., object]] = {
    "matches": _method_matches,
    "startsWith": _method_starts_with,
    "endsWith": _method_ends_with,
    "concat": _method_concat,
    "toLower": lambda value: _string(value, "toLower()").lower(),
    "toUpper": lambda value: _string(value, "toUpper()").upper(),
    "size": lambda value: len(_string(value, "size()")),
}


def _compile_method(node: ast.MethodCall) -> Fn:
    source = _compile(node.source)
    if node.name == "oclIsUndefined":
        return lambda env: source(env) is None
    method = _METHODS[node.name]
    arguments = [_compile(argument) for argument in node.arguments]
    collections = COLLECTION_TYPES

    def apply(value: object, args: list[object]) -> object:
        if isinstance(value, collections):  # implicit collect over the elements
            return tuple(method(element, *args) for element in value if element is not None)
        return method(value, *args)

    if not arguments:
        return lambda env: apply(source(env), [])
    if len(arguments) == 1:
        argument = arguments[0]
        return lambda env: apply(source(env), [argument(env)])
    return lambda env: apply(source(env), [a(env) for a in arguments])


# ---- operations on collections: ``value->name(arguments)``


def _sum(items: Iterable[Any]) -> int | float:
    total: int | float = 0
    for item in items:
        total += _number(item, "sum()")
    return total


def _extreme(items: Iterable[Any], pick: Callable[..., Any], what: str) -> object:
    values = list(items)
    if not values:
        return None
    if all(_is_number(v) for v in values) or all(isinstance(v, str) for v in values):
        return pick(values)
    raise OclEvaluationError(f"{what} expects numbers or strings")


def _includes(items: Any, value: object) -> bool:
    return any(_equal(item, value) for item in items)


_COLLECTION_OPERATIONS: dict[str, Callable[..., object]] = {
    "notEmpty": lambda items: len(items) > 0,
    "isEmpty": lambda items: len(items) == 0,
    "size": len,
    "includes": _includes,
    "excludes": lambda items, value: not _includes(items, value),
    "includesAll": lambda items, other: all(_includes(items, v) for v in _as_collection(other)),
    "excludesAll": lambda items, other: not any(
        _includes(items, v) for v in _as_collection(other)
    ),
    "count": lambda items, value: sum(1 for item in items if _equal(item, value)),
    "sum": _sum,
    "min": lambda items: _extreme(items, min, "min()"),
    "max": lambda items: _extreme(items, max, "max()"),
    "first": lambda items: next(iter(items), None),
    "last": lambda items: tuple(items)[-1] if len(items) else None,
    "asSet": lambda items: OclSet(_unique(items)),
    "asSequence": tuple,
    "union": lambda items, other: tuple(items) + tuple(_as_collection(other)),
}
_FAST_COLLECTION_OPERATIONS = {"notEmpty", "isEmpty", "size"}


def _compile_collection_call(node: ast.CollectionCall) -> Fn:
    source = _compile(node.source)
    collections = COLLECTION_TYPES
    if node.name in _FAST_COLLECTION_OPERATIONS:

        def count(env: Env) -> int:
            value = source(env)
            if isinstance(value, collections):
                return len(value)
            return 0 if value is None else 1

        if node.name == "size":
            return count
        if node.name == "notEmpty":
            return lambda env: count(env) > 0
        return lambda env: count(env) == 0

    operation = _COLLECTION_OPERATIONS[node.name]
    arguments = [_compile(argument) for argument in node.arguments]
    if not arguments:
        return lambda env: operation(_as_collection(source(env)))
    (argument,) = arguments
    return lambda env: operation(_as_collection(source(env)), argument(env))


# ---- iterators: ``value->name(variable | body)``


def _compile_iterate(node: ast.Iterate) -> Fn:
    source, body = _compile(node.source), _compile(node.body)
    variable, name = node.variable, node.name
    what = f"{name}()"

    def bound(loop: Callable[[Any, Env], object]) -> Fn:
        def run(env: Env) -> object:
            items = _as_collection(source(env))
            saved = env.get(variable, _MISSING)
            try:
                return loop(items, env)
            finally:
                if saved is _MISSING:
                    env.pop(variable, None)
                else:
                    env[variable] = saved

        return run

    def predicate(env: Env) -> bool:
        result = body(env)
        if result is True or result is False:
            return result
        return _boolean(result, what)

    def for_all(items: Any, env: Env) -> bool:
        for item in items:
            env[variable] = item
            if not predicate(env):
                return False
        return True

    def exists(items: Any, env: Env) -> bool:
        for item in items:
            env[variable] = item
            if predicate(env):
                return True
        return False

    def select(items: Any, env: Env) -> tuple[Any, ...]:
        kept = []
        for item in items:
            env[variable] = item
            if predicate(env):
                kept.append(item)
        return tuple(kept)

    def reject(items: Any, env: Env) -> tuple[Any, ...]:
        kept = []
        for item in items:
            env[variable] = item
            if not predicate(env):
                kept.append(item)
        return tuple(kept)

    def collect(items: Any, env: Env) -> tuple[Any, ...]:
        result: list[Any] = []
        for item in items:
            env[variable] = item
            value = body(env)
            if isinstance(value, COLLECTION_TYPES):
                result.extend(v for v in value if v is not None)
            elif value is not None:
                result.append(value)
        return tuple(result)

    def any_(items: Any, env: Env) -> object:
        for item in items:
            env[variable] = item
            if predicate(env):
                return item
        return None

    def one(items: Any, env: Env) -> bool:
        found = 0
        for item in items:
            env[variable] = item
            if predicate(env):
                found += 1
                if found > 1:
                    return False
        return found == 1

    def is_unique(items: Any, env: Env) -> bool:
        values = []
        for item in items:
            env[variable] = item
            values.append(body(env))
        return len(_unique(values)) == len(values)

    loops: dict[str, Callable[[Any, Env], object]] = {
        "forAll": for_all,
        "exists": exists,
        "select": select,
        "reject": reject,
        "collect": collect,
        "any": any_,
        "one": one,
        "isUnique": is_unique,
    }
    return bound(loops[name])


# ---- operators


def _compile_unary(node: ast.Unary) -> Fn:
    operand = _compile(node.operand)
    if node.operator == "not":

        def run_not(env: Env) -> bool:
            value = operand(env)
            if value is True:
                return False
            if value is False:
                return True
            return not _boolean(value, "'not'")

        return run_not
    return lambda env: -_number(operand(env), "unary '-'")


def _compile_boolean(operator: str, left: Fn, right: Fn) -> Fn:
    what = f"'{operator}'"
    if operator == "and":

        def run_and(env: Env) -> bool:
            if not _boolean(left(env), what):
                return False
            return _boolean(right(env), what)

        return run_and
    if operator == "or":

        def run_or(env: Env) -> bool:
            if _boolean(left(env), what):
                return True
            return _boolean(right(env), what)

        return run_or
    if operator == "implies":

        def run_implies(env: Env) -> bool:
            if not _boolean(left(env), what):
                return True
            return _boolean(right(env), what)

        return run_implies

    def run_xor(env: Env) -> bool:
        return _boolean(left(env), what) != _boolean(right(env), what)

    return run_xor


def _order(operator: str) -> Callable[[Any, Any], bool]:
    compare: Callable[[Any, Any], bool] = {
        "<": lambda a, b: a < b,
        ">": lambda a, b: a > b,
        "<=": lambda a, b: a <= b,
        ">=": lambda a, b: a >= b,
    }[operator]

    def run(a: Any, b: Any) -> bool:
        if (_is_number(a) and _is_number(b)) or (isinstance(a, str) and isinstance(b, str)):
            return compare(a, b)
        raise OclEvaluationError(
            f"'{operator}' cannot compare {_type_name(a)} with {_type_name(b)}"
        )

    return run


def _add(a: Any, b: Any) -> Any:
    if (_is_number(a) and _is_number(b)) or (isinstance(a, str) and isinstance(b, str)):
        return a + b
    raise OclEvaluationError(f"'+' cannot add {_type_name(a)} and {_type_name(b)}")


def _divide(a: Any, b: Any) -> Any:
    a, b = _number(a, "'/'"), _number(b, "'/'")
    if b == 0:
        raise OclEvaluationError("division by zero")
    return a / b


_BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "=": _equal,
    "<>": lambda a, b: not _equal(a, b),
    "<": _order("<"),
    ">": _order(">"),
    "<=": _order("<="),
    ">=": _order(">="),
    "+": _add,
    "-": lambda a, b: _number(a, "'-'") - _number(b, "'-'"),
    "*": lambda a, b: _number(a, "'*'") * _number(b, "'*'"),
    "/": _divide,
}


def _compile_binary(node: ast.Binary) -> Fn:
    left, right = _compile(node.left), _compile(node.right)
    if node.operator in ("and", "or", "xor", "implies"):
        return _compile_boolean(node.operator, left, right)
    operation = _BINARY[node.operator]
    if node.operator == "=":

        def run_equal(env: Env) -> bool:
            a, b = left(env), right(env)
            if a is b:
                return True
            if type(a) is type(b) and not isinstance(a, COLLECTION_TYPES):
                return bool(a == b)
            return _equal(a, b)

        return run_equal
    return lambda env: operation(left(env), right(env))


def _compile_if(node: ast.If) -> Fn:
    condition, then_branch, else_branch = (
        _compile(node.condition),
        _compile(node.then_branch),
        _compile(node.else_branch),
    )

    def run(env: Env) -> object:
        if _boolean(condition(env), "'if'"):
            return then_branch(env)
        return else_branch(env)

    return run


def _compile_let(node: ast.Let) -> Fn:
    variable, value, body = node.variable, _compile(node.value), _compile(node.body)

    def run(env: Env) -> object:
        bound = value(env)
        saved = env.get(variable, _MISSING)
        env[variable] = bound
        try:
            return body(env)
        finally:
            if saved is _MISSING:
                env.pop(variable, None)
            else:
                env[variable] = saved

    return run


_COMPILERS: dict[type, Callable[[Any], Fn]] = {
    ast.Literal: _compile_literal,
    ast.Variable: _compile_variable,
    ast.Navigation: _compile_navigation,
    ast.MethodCall: _compile_method,
    ast.CollectionCall: _compile_collection_call,
    ast.Iterate: _compile_iterate,
    ast.Unary: _compile_unary,
    ast.Binary: _compile_binary,
    ast.If: _compile_if,
    ast.Let: _compile_let,
}

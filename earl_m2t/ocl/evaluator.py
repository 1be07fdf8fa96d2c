"""Evaluation of OCL expressions over plain Python objects.

An expression tree is compiled once into nested Python closures; each closure takes the
environment (a dict from variable name to value, ``self`` included) and returns a value.
Iterators (:mod:`earl_m2t.ocl.iterators`) and ``let`` bind their variable in that dict and
restore it afterwards; what the named operations and operators do is in
:mod:`earl_m2t.ocl.operations`, the value helpers in :mod:`earl_m2t.ocl.values`.

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

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import earl_m2t.ocl.ast as ast
from earl_m2t.ocl.errors import OclEvaluationError
from earl_m2t.ocl.iterators import compile_iterator
from earl_m2t.ocl.operations import BINARY, COLLECTION_OPERATIONS, METHODS
from earl_m2t.ocl.values import (
    COLLECTION_TYPES,
    UNBOUND,
    Env,
    Fn,
    as_collection,
    attribute,
    boolean,
    equal,
    navigate,
    number,
)


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
            return navigate(value, name)
        try:
            return getattr(value, name)
        except AttributeError:
            return attribute(value, name)  # raises the located error

    return run


# ---- operations on single values: ``value.name(arguments)``


def _compile_method(node: ast.MethodCall) -> Fn:
    source = _compile(node.source)
    if node.name == "oclIsUndefined":
        return lambda env: source(env) is None
    method = METHODS[node.name]
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

    operation = COLLECTION_OPERATIONS[node.name]
    arguments = [_compile(argument) for argument in node.arguments]
    if not arguments:
        return lambda env: operation(as_collection(source(env)))
    (argument,) = arguments
    return lambda env: operation(as_collection(source(env)), argument(env))


# ---- iterators: ``value->name(variable | body)``


def _compile_iterate(node: ast.Iterate) -> Fn:
    return compile_iterator(node.name, node.variable, _compile(node.source), _compile(node.body))


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
            return not boolean(value, "'not'")

        return run_not
    return lambda env: -number(operand(env), "unary '-'")


def _compile_boolean(operator: str, left: Fn, right: Fn) -> Fn:
    what = f"'{operator}'"
    if operator == "and":

        def run_and(env: Env) -> bool:
            if not boolean(left(env), what):
                return False
            return boolean(right(env), what)

        return run_and
    if operator == "or":

        def run_or(env: Env) -> bool:
            if boolean(left(env), what):
                return True
            return boolean(right(env), what)

        return run_or
    if operator == "implies":

        def run_implies(env: Env) -> bool:
            if not boolean(left(env), what):
                return True
            return boolean(right(env), what)

        return run_implies

    def run_xor(env: Env) -> bool:
        return boolean(left(env), what) != boolean(right(env), what)

    return run_xor


def _compile_binary(node: ast.Binary) -> Fn:
    left, right = _compile(node.left), _compile(node.right)
    if node.operator in ("and", "or", "xor", "implies"):
        return _compile_boolean(node.operator, left, right)
    operation = BINARY[node.operator]
    if node.operator == "=":

        def run_equal(env: Env) -> bool:
            a, b = left(env), right(env)
            if a is b:
                return True
            if type(a) is type(b) and not isinstance(a, COLLECTION_TYPES):
                return bool(a == b)
            return equal(a, b)

        return run_equal
    return lambda env: operation(left(env), right(env))


def _compile_if(node: ast.If) -> Fn:
    condition, then_branch, else_branch = (
        _compile(node.condition),
        _compile(node.then_branch),
        _compile(node.else_branch),
    )

    def run(env: Env) -> object:
        if boolean(condition(env), "'if'"):
            return then_branch(env)
        return else_branch(env)

    return run


def _compile_let(node: ast.Let) -> Fn:
    variable, value, body = node.variable, _compile(node.value), _compile(node.body)

    def run(env: Env) -> object:
        bound = value(env)
        saved = env.get(variable, UNBOUND)
        env[variable] = bound
        try:
            return body(env)
        finally:
            if saved is UNBOUND:
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

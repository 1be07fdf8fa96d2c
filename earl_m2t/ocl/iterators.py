"""OCL's iterators, ``source->name(variable | body)``, compiled from their compiled parts.

The variable is bound in the environment to each element in turn and restored afterwards;
``forAll``, ``exists``, ``select``, ``reject``, ``any`` and ``one`` require the body to give
``true`` or ``false``, and ``forAll``, ``exists``, ``any`` and ``one`` stop as soon as the
answer is known.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from earl_m2t.ocl.values import COLLECTION_TYPES, UNBOUND, Env, Fn, as_collection, boolean, unique

Loop = Callable[[Any, Env], object]  # runs over the items, the variable bound to each in turn
Predicate = Callable[[Env], bool]


def compile_iterator(name: str, variable: str, source: Fn, body: Fn) -> Fn:
    """``source->name(variable | body)``, given the compiled source and body."""
    what = f"{name}()"

    def predicate(env: Env) -> bool:
        result = body(env)
        if result is True or result is False:
            return result
        return boolean(result, what)

    loop = _LOOPS[name](variable, body, predicate)

    def run(env: Env) -> object:
        items = as_collection(source(env))
        saved = env.get(variable, UNBOUND)
        try:
            return loop(items, env)
        finally:
            if saved is UNBOUND:
                env.pop(variable, None)
            else:
                env[variable] = saved

    return run


def _for_all(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def for_all(items: Any, env: Env) -> bool:
        for item in items:
            env[variable] = item
            if not predicate(env):
                return False
        return True

    return for_all


def _exists(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def exists(items: Any, env: Env) -> bool:
        for item in items:
            env[variable] = item
            if predicate(env):
                return True
        return False

    return exists


def _select(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def select(items: Any, env: Env) -> tuple[Any, ...]:
        kept = []
        for item in items:
            env[variable] = item
            if predicate(env):
                kept.append(item)
        return tuple(kept)

    return select


def _reject(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def reject(items: Any, env: Env) -> tuple[Any, ...]:
        kept = []
        for item in items:
            env[variable] = item
            if not predicate(env):
                kept.append(item)
        return tuple(kept)

    return reject


def _collect(variable: str, body: Fn, predicate: Predicate) -> Loop:
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

    return collect


def _any(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def any_(items: Any, env: Env) -> object:
        for item in items:
            env[variable] = item
            if predicate(env):
                return item
        return None

    return any_


def _one(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def one(items: Any, env: Env) -> bool:
        found = 0
        for item in items:
            env[variable] = item
            if predicate(env):
                found += 1
                if found > 1:
                    return False
        return found == 1

    return one


def _is_unique(variable: str, body: Fn, predicate: Predicate) -> Loop:
    def is_unique(items: Any, env: Env) -> bool:
        values = []
        for item in items:
            env[variable] = item
            values.append(body(env))
        return len(unique(values)) == len(values)

    return is_unique


_LOOPS: dict[str, Callable[[str, Fn, Predicate], Loop]] = {
    "forAll": _for_all,
    "exists": _exists,
    "select": _select,
    "reject": _reject,
    "collect": _collect,
    "any": _any,
    "one": _one,
    "isUnique": _is_unique,
}

"""Token-level mutations of SysML v2 text: a keyword, operator, bracket or number replaced or
inserted, a name quoted with hostile characters (spaces, newlines, ``--``, backslashes, quotes,
``%``), a guard made long or deep, quantifiers nested (``any K: any K: …``). The tokens come
from ``mutate._TOKEN``'s split; every choice draws from the ``random.Random`` given."""

from __future__ import annotations

import random

from tests.fuzz.mutate_xmi import HOSTILE_NUMBERS

KEYWORDS = (
    "package", "part", "def", "port", "attribute", "state", "transition", "first", "then", "if", "accept",
    "do", "entry", "exit", "action", "calc", "import", "private", "public", "in", "out", "inout", "metadata",
    "about", "language", "enum", "item", "ref", "abstract", "variation", "true", "false", "null", "not",
    "and", "or", "xor", "implies", "all", "any", "specializes", "subsets", "redefines", "end", "doc",
)
OPERATORS = (
    "and", "or", "xor", "not", "implies", "==", "!=", "===", "<", ">", "<=", ">=", "+", "-", "*", "/",
    "**", "%", "^", "@", "::", ".", "?", "??", "->", "=", ":=", ":>", ":>>", "~", "|", "&", "#", "$",
)
BRACKETS = ("{", "}", "(", ")", "[", "]", "/*", "*/", "'", '"')
QUOTED_HOSTILE = (
    "a b", "a\nb", "a\r\nb", "x--y", "--", "a\\b", "\\", "\\'", "it's", 'say "hi"', "100%", "%s%d%n", "a/*b*/c",
    "a//b", "#{x}", " ", "\t", "'", "K", "any K:",
)


def _quote(text: str) -> str:
    return "'" + text.replace("\\", "\\\\").replace("'", "\\'") + "'"


def long_guard(rng: random.Random) -> str:
    """A guard of many terms, deep parentheses or nested quantifiers, as SysML v2 or EARL text."""
    kind = rng.randrange(5)
    if kind == 0:
        return " and ".join(f"'p{i}/pp'()" for i in range(rng.choice((50, 2_000, 12_000))))
    if kind == 1:
        depth = rng.choice((10, 150, 199, 201, 400))
        return "(" * depth + "'p/pp'()" + ")" * depth
    if kind == 2:
        return "not " * rng.choice((10, 199, 201, 500)) + "'p/pp'()"
    if kind == 3:
        nested = rng.choice((2, 3, 6, 12))
        variable = rng.choice(("K", "K", "J"))
        return "language \"EARL\" /* " + "".join(f"any {variable}: " for _ in range(nested)) + "a/mi.x[K] */"
    return "language \"EARL\" /* " + " ∧ ".join("(" * 30 + f"a{i}/mi.x" + ")" * 30 for i in range(40)) + " */"


def mutate_tokens(tokens: list[str], rng: random.Random) -> list[str]:
    """One token-level change of SysML v2 text split into tokens."""
    kind = rng.randrange(7)
    at = rng.randrange(len(tokens))
    words = [i for i, token in enumerate(tokens) if token[:1].isalpha() or token[:1] == "_"]
    numbers = [i for i, token in enumerate(tokens) if token[:1].isdigit()]
    if kind == 0 and words:
        tokens[rng.choice(words)] = rng.choice(KEYWORDS)
    elif kind == 1:
        tokens.insert(at, f" {rng.choice(OPERATORS)} ")
    elif kind == 2:
        if rng.random() < 0.5:
            tokens.insert(at, rng.choice(BRACKETS))
        else:
            brackets = [i for i, token in enumerate(tokens) if token in BRACKETS]
            if brackets:
                del tokens[rng.choice(brackets)]
    elif kind == 3:
        where = rng.choice(numbers) if numbers else at
        value = rng.choice(HOSTILE_NUMBERS)
        if numbers:
            tokens[where] = value
        else:
            tokens.insert(where, value)
    elif kind == 4 and words:
        tokens[rng.choice(words)] = _quote(rng.choice(QUOTED_HOSTILE) * rng.choice((1, 1, 3, 1000)))
    else:
        guards = [i for i, token in enumerate(tokens) if token == "if"]
        guard = long_guard(rng)
        if guards and not guard.startswith("language"):
            tokens.insert(rng.choice(guards) + 1, f" {guard} and ")
        else:
            languages = [i for i, token in enumerate(tokens) if token.startswith("/*") and i > 2
                         and tokens[i - 2] == '"EARL"']
            if languages and guard.startswith("language"):
                tokens[rng.choice(languages)] = guard.split(" ", 2)[2]
            else:
                tokens.insert(at, guard)
    return tokens

"""Tree rewrites: index substitution, expansion of replications, n-ary joins."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import replace
from typing import Literal, cast

from earl_m2t.model.limits import MAX_EXPANSION
from earl_m2t.model.naming import split
from earl_m2t.predicate.ast import (
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
    children,
)
from earl_m2t.predicate.errors import PredicateSyntaxError, where


def map_children(node: Node, fn: Callable[[Node], Node]) -> Node:
    """Return ``node`` with ``fn`` applied to each of its direct sub-nodes.

    ``fn`` keeps the kind of what it maps (an expression stays an expression, a field a field).
    """
    if isinstance(node, Not):
        return replace(node, operand=cast(Expr, fn(node.operand)))
    if isinstance(node, (And, Or)):
        return replace(node, operands=tuple(cast(Expr, fn(o)) for o in node.operands))
    if isinstance(node, NewData):
        return replace(node, ref=cast(FieldRef, fn(node.ref)))
    if isinstance(node, Compare):
        return replace(node, left=cast(Operand, fn(node.left)), right=cast(Operand, fn(node.right)))
    if isinstance(node, Replicated):
        return replace(node, template=cast(Expr, fn(node.template)))
    return node


def join(op: Literal["and", "or"], operands: list[Expr] | tuple[Expr, ...], *,
         line: int = 1, column: int = 1) -> Expr:
    """Join operands by ``op``, flattening nested chains of the same operator.

    No operand gives the neutral element (``TRUE`` for and, ``FALSE`` for or); a single
    operand is returned as is.
    """
    if len(operands) == 1:
        return operands[0]
    kind = And if op == "and" else Or
    flat: list[Expr] = []
    for operand in operands:
        if isinstance(operand, kind):
            flat.extend(operand.operands)
        else:
            flat.append(operand)
    if not flat:
        return Const(op == "and", line=line, column=column)
    return kind(tuple(flat), line=line, column=column)


def index_name(name: str, var: str, value: int | str) -> str:
    """Put ``value`` in place of the index placeholder ``var`` of a name.

    Only the end of the descriptive name, before the ``/abbr`` suffix, is an index
    position: ``index_name("motorControllerStateK/ib", "K", 3)`` is
    ``"motorControllerState3/ib"``; ``"Kinematics/ib"`` and a name that is just ``K``
    stay as they are.
    """
    base, suffix = split(name)
    if len(base) > len(var) and base.endswith(var):
        base = base[: -len(var)] + str(value)
    return base if suffix is None else f"{base}/{suffix}"


def is_indexed(name: str, var: str) -> bool:
    """True when ``name`` carries the placeholder ``var`` in its index position."""
    return index_name(name, var, "") != name


def substitute_index(expr: Expr, var: str, value: int | str) -> Expr:
    """Replace the index placeholder ``var`` by ``value`` in every head name of ``expr``.

    A nested :class:`Replicated` over the same ``var`` binds it anew and is left alone.
    """

    def visit(node: Node) -> Node:
        if isinstance(node, PredicateRef):
            return replace(node, name=index_name(node.name, var, value))
        if isinstance(node, FieldRef):
            return replace(node, head=index_name(node.head, var, value))
        if isinstance(node, Replicated) and node.var == var:
            return node
        return map_children(node, visit)

    return visit(expr)  # type: ignore[return-value]


class ExpansionRefused(ValueError):
    """The replications of an expression cannot be written out: one rebinds the variable of a
    replication it is in, or all of them together expand beyond ``MAX_EXPANSION`` nodes."""

    def __init__(self, message: str, node: Replicated) -> None:
        super().__init__(message)
        self.message = message
        self.line = node.line
        self.column = node.column


def _expanded_size(node: Node, count_for: Callable[[Replicated], int | None], bound: int,
                   binding: frozenset[str] = frozenset()) -> int:
    """The nodes ``node`` expands to (counted up to just past ``bound``); raises ExpansionRefused
    for a replication inside one of the same variable."""
    if isinstance(node, Replicated):
        if node.var in binding:
            raise ExpansionRefused(f"a replication over {node.var} inside another over {node.var}: each "
                                   "replication needs its own variable", node)
        count = count_for(node)
        inner = _expanded_size(node.template, count_for, bound, binding | {node.var})
        return inner if count is None else min(max(count, 1) * inner, bound + 1)
    size = 1
    for child in children(node):
        size = min(size + _expanded_size(child, count_for, bound, binding), bound + 1)
    return size


def expand_replicated(expr: Expr, count_for: Callable[[Replicated], int | None]) -> Expr:
    """Replace each :class:`Replicated` by the And / Or of its template over ``var`` = 1..N.

    ``count_for`` gives N for a replication (the multiplicity of the replicated
    instances); None leaves that node, template included, as it is. N = 0 gives the
    neutral element (``FALSE`` for or, ``TRUE`` for and), N = 1 the single instance.
    Chains are flattened again: ``x ∨ a1 ∨ … ∨ aN`` with N = 2 becomes ``x ∨ a1 ∨ a2``.
    Raises ExpansionRefused, before expanding anything, for a replication over the variable of
    one it is in, or for more than ``MAX_EXPANSION`` nodes in all.
    """
    counts: dict[int, int | None] = {}

    def counted(node: Replicated) -> int | None:  # count_for once per replication
        if id(node) not in counts:
            counts[id(node)] = count_for(node)
        return counts[id(node)]

    first = next((n for n in _walk(expr) if isinstance(n, Replicated)), None)
    if first is None:  # nothing to expand: a long expression is not an expansion
        return expr
    if _expanded_size(expr, counted, MAX_EXPANSION) > MAX_EXPANSION:
        raise ExpansionRefused(f"its replications expand to more than {MAX_EXPANSION} terms", first)

    def visit(node: Node) -> Node:
        if isinstance(node, Replicated):
            count = counted(node)
            if count is None:
                return node
            if count < 0:
                raise ValueError(f"negative replication count {count}")
            copies = [visit(substitute_index(node.template, node.var, k))
                      for k in range(1, count + 1)]
            return join(node.op, copies,  # type: ignore[arg-type]
                        line=node.line, column=node.column)
        node = map_children(node, visit)
        if isinstance(node, And):
            return join("and", node.operands, line=node.line, column=node.column)
        if isinstance(node, Or):
            return join("or", node.operands, line=node.line, column=node.column)
        return node

    return visit(expr)  # type: ignore[return-value]


def _walk(node: Node) -> Iterator[Node]:
    yield node
    for child in children(node):
        yield from _walk(child)


class OperandsDiffer(Exception):
    """The operands of a replication ``first ∨ … ∨ last`` differ in more than their index,
    first at ``before`` (in ``first``) and ``after`` (in ``last``).

    The parser turns it into a :class:`PredicateSyntaxError` that shows both as text. The text
    is not made here: the printer makes it, and the printer itself asks
    :func:`replication_template` whether a replication can be written in the paper's form.
    """

    def __init__(self, before: Node, after: Node, last_index: str) -> None:
        super().__init__(before, after, last_index)
        self.before = before
        self.after = after
        self.last_index = last_index


def replication_template(first: Expr, last: Expr, *, var: str = "K", last_index: str = "N",
                         line: int = 1, column: int = 1) -> Expr:
    """The template of the replication form ``first ∨ … ∨ last``.

    ``first`` must name the replicated instances with index 1 and ``last`` with index
    ``last_index`` (N), and be otherwise identical; the template carries ``var`` in their
    place. ``line`` and ``column`` locate the ellipsis, for the error when no name is
    indexed. At the first difference, raises :class:`PredicateSyntaxError` when it is in an
    index, else :class:`OperandsDiffer`.
    """
    unifier = _Unifier(var, last_index)
    template = unifier.unify(first, last)
    if not unifier.indexed:
        raise PredicateSyntaxError(
            f"no replicated name around '…' at {where(line, column)}: write the operand "
            f"before it with index 1 and the one after it with index {last_index} "
            f"(e.g. 'motor1/ib ∨ … ∨ motor{last_index}/ib')",
            line,
            column,
        )
    return cast(Expr, template)


class _Unifier:
    """Walks the first and the last operand of a replication side by side."""

    def __init__(self, var: str, last_index: str) -> None:
        self.var = var
        self.last_index = last_index
        self.indexed = False

    def unify(self, a: Node, b: Node) -> Node:
        if type(a) is not type(b):
            raise self._mismatch(a, b)
        if isinstance(a, PredicateRef):
            return replace(a, name=self._name(a, a.name, b, b.name))  # type: ignore[union-attr]
        if isinstance(a, FieldRef):
            assert isinstance(b, FieldRef)
            if (a.member, a.path) != (b.member, b.path):
                raise self._mismatch(a, b)
            return replace(a, head=self._name(a, a.head, b, b.head))
        if isinstance(a, (Const, Number)):
            if a != b:
                raise self._mismatch(a, b)
            return a
        if isinstance(a, (And, Or)):
            assert isinstance(b, (And, Or))
            if len(a.operands) != len(b.operands):
                raise self._mismatch(a, b)
        elif isinstance(a, Compare):
            assert isinstance(b, Compare)
            if a.op != b.op:
                raise self._mismatch(a, b)
        elif isinstance(a, Replicated):
            assert isinstance(b, Replicated)
            if (a.op, a.var) != (b.op, b.var):
                raise self._mismatch(a, b)
        pairs = iter(children(b))
        return map_children(a, lambda child: self.unify(child, next(pairs)))

    def _name(self, a: Node, first: str, b: Node, last: str) -> str:
        if first == last:
            return first
        (base1, suffix1), (base_n, suffix_n) = split(first), split(last)
        if suffix1 == suffix_n and len(base1) > 1 and len(base_n) > len(self.last_index):
            stem1, stem_n = base1[:-1], base_n[: -len(self.last_index)]
            ends1, ends_n = base1.endswith("1"), base_n.endswith(self.last_index)
            if ends1 and ends_n and stem1 == stem_n:
                self.indexed = True
                name = stem1 + self.var
                return name if suffix1 is None else f"{name}/{suffix1}"
            if ends_n and not ends1 and base1[:-1] == stem_n:
                raise _error(a, f"the operand before '…' must use index 1, found '{first}'")
            if ends1 and not ends_n and base_n[:-1] == stem1:
                raise _error(b, f"the operand after '…' must use index {self.last_index}, "
                                f"found '{last}'")
        raise self._mismatch(a, b)

    def _mismatch(self, a: Node, b: Node) -> OperandsDiffer:
        return OperandsDiffer(a, b, self.last_index)


def _error(node: Node, message: str) -> PredicateSyntaxError:
    return PredicateSyntaxError(f"{message} at {where(node.line, node.column)}",
                                node.line, node.column)

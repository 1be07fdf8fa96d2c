"""Propositional formulas in CNF for the SAT solver (MiniSat 2.2 through PySAT, ``python-sat``).

Formulas are predicate trees (:mod:`earl_m2t.predicate`) built from ``TRUE``/``FALSE``,
``¬ ∧ ∨`` and *atoms*: every other node (a field, ``newData(...)``, a comparison, an opaque
primitive predicate) is one propositional variable, and equal atoms (positions ignored) are
the same variable. Each sub-formula gets a variable defined by Tseitin clauses (both
directions, so a satisfying assignment gives every sub-formula its true value); a query
asserts some literals and asks for a model.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from earl_m2t.predicate import And, Const, Expr, Not, Or


class Cnf:
    """A growing set of Tseitin definitions over one pool of variables."""

    def __init__(self) -> None:
        self._count = 0
        self.atoms: dict[Expr, int] = {}  # atom node -> variable
        self._defined: dict[int, tuple[Expr, int]] = {}  # id(node) -> (node kept alive, literal)
        self._clauses: dict[int, list[list[int]]] = {}  # defined variable -> its clauses
        self._children: dict[int, tuple[int, ...]] = {}  # defined variable -> operand variables
        self.true = self._new()
        self._clauses[self.true] = [[self.true]]
        self.calls = 0  # solver calls, for benchmarks and tests

    def _new(self) -> int:
        self._count += 1
        return self._count

    def literal(self, expr: Expr) -> int:
        """The literal that is true exactly when ``expr`` is."""
        known = self._defined.get(id(expr))
        if known is not None:
            return known[1]
        lit = self._encode(expr)
        self._defined[id(expr)] = (expr, lit)
        return lit

    def _encode(self, expr: Expr) -> int:
        if isinstance(expr, Const):
            return self.true if expr.value else -self.true
        if isinstance(expr, Not):
            return -self.literal(expr.operand)
        if isinstance(expr, (And, Or)):
            operands = [self.literal(o) for o in expr.operands]
            var = self._new()
            if isinstance(expr, And):  # var <-> o1 ∧ … ∧ on
                clauses = [[-var, o] for o in operands] + [[var] + [-o for o in operands]]
            else:  # var <-> o1 ∨ … ∨ on
                clauses = [[var, -o] for o in operands] + [[-var] + operands]
            self._clauses[var] = clauses
            self._children[var] = tuple(abs(o) for o in operands)
            return var
        atom = self.atoms.get(expr)
        if atom is None:
            atom = self.atoms[expr] = self._new()
        return atom

    def _cone(self, literals: Iterable[int]) -> list[list[int]]:
        """The definitions the variables of ``literals`` depend on."""
        clauses: list[list[int]] = list(self._clauses[self.true])
        seen: set[int] = {self.true}
        stack = [abs(lit) for lit in literals]
        while stack:
            var = stack.pop()
            if var in seen:
                continue
            seen.add(var)
            clauses.extend(self._clauses.get(var, ()))
            stack.extend(self._children.get(var, ()))
        return clauses

    def solve(self, assumed: Sequence[int], clause: Sequence[int] = ()) -> set[int] | None:
        """A model (the set of true literals) where every ``assumed`` literal holds and,
        if given, at least one literal of ``clause``; None when there is none."""
        clauses = self._cone([*assumed, *clause])
        clauses.extend([lit] for lit in assumed)
        if clause:
            clauses.append(list(clause))
        self.calls += 1
        from pysat.solvers import Solver  # loaded only when a query reaches the solver

        with Solver(name="minisat22", bootstrap_with=clauses) as solver:
            if not solver.solve():
                return None
            model = set(solver.get_model() or ())
        # variables the queried clauses do not mention are false, as in a complete assignment
        model.update(-var for var in range(1, self._count + 1) if var not in model and -var not in model)
        return model

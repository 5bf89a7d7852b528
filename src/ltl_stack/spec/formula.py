"""Propositional formulas over current and next-state (primed) Boolean variables.

Every reader produces these nodes and every consumer (synthesis, rendering, analysis) reads them.
Integer variables never appear here: readers bit-blast them into Boolean variables first
(see ``ltl_stack.spec.model.IntegerVariable``).
"""
from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Var:
    """A Boolean variable; ``primed`` means its value in the next state (``x'``)."""

    name: str
    primed: bool = False


@dataclass(frozen=True, slots=True)
class Const:
    value: bool


@dataclass(frozen=True, slots=True)
class Not:
    arg: Formula


@dataclass(frozen=True, slots=True)
class And:
    """Conjunction of two or more formulas (an empty tuple means true)."""

    args: tuple[Formula, ...]


@dataclass(frozen=True, slots=True)
class Or:
    """Disjunction of two or more formulas (an empty tuple means false)."""

    args: tuple[Formula, ...]


@dataclass(frozen=True, slots=True)
class Xor:
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class Implies:
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class Iff:
    left: Formula
    right: Formula


Formula = Var | Const | Not | And | Or | Xor | Implies | Iff

TRUE = Const(True)
FALSE = Const(False)


def children(f: Formula) -> tuple[Formula, ...]:
    """The direct subformulas of ``f``."""
    if isinstance(f, (Var, Const)):
        return ()
    if isinstance(f, Not):
        return (f.arg,)
    if isinstance(f, (And, Or)):
        return f.args
    return (f.left, f.right)


def walk(f: Formula) -> Iterator[Formula]:
    """Every node of ``f``, parents before children, without recursion (specs can be deep)."""
    stack = [f]
    while stack:
        node = stack.pop()
        yield node
        stack.extend(reversed(children(node)))


def variables(f: Formula) -> set[Var]:
    """The variables (with their primes) that occur in ``f``."""
    return {node for node in walk(f) if isinstance(node, Var)}


def evaluate(f: Formula, current: dict[str, bool], nxt: dict[str, bool] | None = None) -> bool:
    """Truth value of ``f`` with unprimed variables from ``current`` and primed ones from ``nxt``."""
    if isinstance(f, Var):
        source = nxt if f.primed else current
        if source is None or f.name not in source:
            raise KeyError(f"{f.name}{chr(39) if f.primed else ''} has no value")
        return source[f.name]
    if isinstance(f, Const):
        return f.value
    if isinstance(f, Not):
        return not evaluate(f.arg, current, nxt)
    if isinstance(f, And):
        return all(evaluate(a, current, nxt) for a in f.args)
    if isinstance(f, Or):
        return any(evaluate(a, current, nxt) for a in f.args)
    left = evaluate(f.left, current, nxt)
    right = evaluate(f.right, current, nxt)
    if isinstance(f, Xor):
        return left != right
    if isinstance(f, Implies):
        return (not left) or right
    return left == right

"""Propositional formulas over current and next-state (primed) Boolean variables.

Every reader produces these nodes and every consumer (synthesis, rendering, analysis) reads them.
Integer variables never appear here: readers bit-blast them into Boolean variables first
(see ``ltl_stack.spec.model.IntegerVariable``). Nodes have ``__slots__`` (no per-node ``__dict__``): a
formula read from an 8 MB line has millions of them.
"""
from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Union

from ltl_stack.compat import slotted


@slotted
@dataclass(frozen=True)
class Var:
    """A Boolean variable; ``primed`` means its value in the next state (``x'``)."""

    name: str
    primed: bool = False


@slotted
@dataclass(frozen=True)
class Const:
    value: bool


@slotted
@dataclass(frozen=True)
class Not:
    arg: Formula


@slotted
@dataclass(frozen=True)
class And:
    """Conjunction of two or more formulas (an empty tuple means true)."""

    args: tuple[Formula, ...]


@slotted
@dataclass(frozen=True)
class Or:
    """Disjunction of two or more formulas (an empty tuple means false)."""

    args: tuple[Formula, ...]


@slotted
@dataclass(frozen=True)
class Xor:
    left: Formula
    right: Formula


@slotted
@dataclass(frozen=True)
class Implies:
    left: Formula
    right: Formula


@slotted
@dataclass(frozen=True)
class Iff:
    left: Formula
    right: Formula


Formula = Union[Var, Const, Not, And, Or, Xor, Implies, Iff]

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
    """Every distinct node of ``f`` once, parents before children, without recursion (specs can be
    deep). A subformula shared by several parents (slugsin's ``$`` buffers) is visited once: the
    work is linear in the size of the formula's DAG, not in the size of its expansion."""
    seen: set[int] = set()
    stack = [f]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        yield node
        stack.extend(reversed(children(node)))


def variables(f: Formula) -> set[Var]:
    """The variables (with their primes) that occur in ``f``."""
    return {node for node in walk(f) if isinstance(node, Var)}


def evaluate(f: Formula, current: dict[str, bool], nxt: dict[str, bool] | None = None) -> bool:
    """Truth value of ``f`` with unprimed variables from ``current`` and primed ones from ``nxt``.

    Each distinct subformula is evaluated at most once (a shared one's value is remembered), so the
    work is linear in the size of the formula's DAG; ``&`` and ``|`` stop at the first operand that
    decides them. A variable without a value raises ``KeyError``."""
    known: dict[int, bool] = {}

    def value(g: Formula) -> bool:
        got = known.get(id(g))
        if got is None:
            got = known[id(g)] = _value(g)
        return got

    def _value(g: Formula) -> bool:
        if isinstance(g, Var):
            source = nxt if g.primed else current
            if source is None or g.name not in source:
                raise KeyError(f"{g.name}{chr(39) if g.primed else ''} has no value")
            return source[g.name]
        if isinstance(g, Const):
            return g.value
        if isinstance(g, Not):
            return not value(g.arg)
        if isinstance(g, And):
            return all(value(a) for a in g.args)
        if isinstance(g, Or):
            return any(value(a) for a in g.args)
        left, right = value(g.left), value(g.right)
        if isinstance(g, Xor):
            return left != right
        if isinstance(g, Implies):
            return (not left) or right
        return left == right

    return value(f)

"""Operations on formulas that every reader and writer shares, all without recursion.

Specs compiled by slugs are deep (long ``& & & …`` chains) and share subformulas through
``$ n … ? i`` buffers, so a formula is a DAG: ``fold`` evaluates each distinct node once and never
recurses, which keeps both the Python stack and the work linear in the DAG's size.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from ltl_stack.spec.formula import FALSE, TRUE, And, Const, Formula, Iff, Implies, Not, Or, Var, Xor, children

R = TypeVar("R")


def fold(f: Formula, combine: Callable[[Formula, tuple], R]) -> R:
    """Bottom-up evaluation: ``combine(node, results_of_its_children)``, once per distinct node."""
    memo: dict[int, R] = {}
    stack = [f]
    while stack:
        node = stack[-1]
        key = id(node)
        if key in memo:
            stack.pop()
            continue
        kids = children(node)
        pending = [k for k in kids if id(k) not in memo]
        if pending:
            stack.extend(pending)
            continue
        stack.pop()
        memo[key] = combine(node, tuple(memo[id(k)] for k in kids))
    return memo[id(f)]


def conjunction(args: list[Formula] | tuple[Formula, ...]) -> Formula:
    """``And`` of ``args`` with nested conjunctions merged; one argument is itself, none is true."""
    return _junction(And, args, TRUE)


def disjunction(args: list[Formula] | tuple[Formula, ...]) -> Formula:
    """``Or`` of ``args`` with nested disjunctions merged; one argument is itself, none is false."""
    return _junction(Or, args, FALSE)


def _junction(kind: type, args, empty: Formula) -> Formula:
    flat: list[Formula] = []
    for a in args:
        if isinstance(a, kind):
            flat.extend(a.args)
        else:
            flat.append(a)
    if not flat:
        return empty
    if len(flat) == 1:
        return flat[0]
    return kind(tuple(flat))


def flatten(f: Formula) -> Formula:
    """``f`` with nested ``And``/``Or`` merged and 0- or 1-argument ones removed.

    This is the form both readers produce: ``& a & b c`` and ``a & b & c`` are ``And((a, b, c))``.
    """
    def combine(node: Formula, kids: tuple) -> Formula:
        if isinstance(node, And):
            return conjunction(kids)
        if isinstance(node, Or):
            return disjunction(kids)
        return _rebuild(node, kids)
    return fold(f, combine)


def prefix_normal_form(f: Formula) -> Formula:
    """What ``parse_slugsin(write_slugsin(...))`` gives back for ``f``.

    slugsin has only ``! & | ^``, so ``a -> b`` is written ``| ! a b`` and ``a <-> b`` as ``! ^ a b``;
    conjunctions and disjunctions are flattened as by ``flatten``.
    """
    def combine(node: Formula, kids: tuple) -> Formula:
        if isinstance(node, And):
            return conjunction(kids)
        if isinstance(node, Or):
            return disjunction(kids)
        if isinstance(node, Implies):
            return disjunction([Not(kids[0]), kids[1]])
        if isinstance(node, Iff):
            return Not(Xor(kids[0], kids[1]))
        return _rebuild(node, kids)
    return fold(f, combine)


def map_vars(f: Formula, replace: Callable[[Var], Formula]) -> Formula:
    """``f`` with every variable ``v`` replaced by ``replace(v)``; shared subformulas stay shared, and
    parts in which nothing changed are the same objects."""
    return fold(f, lambda node, kids: replace(node) if isinstance(node, Var) else _rebuild(node, kids))


def _rebuild(node: Formula, kids: tuple) -> Formula:
    """``node`` with new children (the same object when nothing changed, to keep sharing)."""
    if all(a is b for a, b in zip(kids, children(node))):
        return node
    if isinstance(node, Not):
        return Not(kids[0])
    if isinstance(node, And):
        return And(kids)
    if isinstance(node, Or):
        return Or(kids)
    return type(node)(kids[0], kids[1])


def size(f: Formula) -> int:
    """Number of distinct nodes of ``f`` (shared subformulas count once)."""
    return len(_distinct(f))


def _distinct(f: Formula) -> set[int]:
    seen: set[int] = set()
    stack = [f]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        stack.extend(children(node))
    return seen


def depth(f: Formula) -> int:
    """Length of the longest path from ``f`` to a leaf (a variable alone has depth 1)."""
    return fold(f, lambda node, kids: 1 + max(kids, default=0))


def evaluate_many(f: Formula, current: dict[str, int], nxt: dict[str, int] | None, mask: int) -> int:
    """Evaluate ``f`` on many valuations at once: bit ``k`` of each value is variable's value in sample ``k``.

    ``mask`` has a 1 for every sample. Without recursion and once per shared node, so it is fast
    enough to compare large compiled specs on hundreds of random valuations.
    """
    def combine(node: Formula, kids: tuple) -> int:
        if isinstance(node, Var):
            source = nxt if node.primed else current
            if source is None or node.name not in source:
                raise KeyError(f"{node.name}{chr(39) if node.primed else ''} has no value")
            return source[node.name] & mask
        if isinstance(node, Const):
            return mask if node.value else 0
        if isinstance(node, Not):
            return ~kids[0] & mask
        if isinstance(node, And):
            value = mask
            for k in kids:
                value &= k
            return value
        if isinstance(node, Or):
            value = 0
            for k in kids:
                value |= k
            return value
        if isinstance(node, Xor):
            return kids[0] ^ kids[1]
        if isinstance(node, Implies):
            return (~kids[0] | kids[1]) & mask
        return ~(kids[0] ^ kids[1]) & mask
    return fold(f, combine)


# Constructors that fold constants; the integer bit-blasting uses them so that ``x = 3`` gives a
# small formula instead of one full of ``& 1 …`` and ``| 0 …``.

def not_(a: Formula) -> Formula:
    if isinstance(a, Const):
        return FALSE if a.value else TRUE
    if isinstance(a, Not):
        return a.arg
    return Not(a)


def and_(a: Formula, b: Formula) -> Formula:
    for x, y in ((a, b), (b, a)):
        if isinstance(x, Const):
            return y if x.value else FALSE
    return conjunction([a, b])


def or_(a: Formula, b: Formula) -> Formula:
    for x, y in ((a, b), (b, a)):
        if isinstance(x, Const):
            return TRUE if x.value else y
    return disjunction([a, b])


def xor_(a: Formula, b: Formula) -> Formula:
    if isinstance(a, Const):
        return not_(b) if a.value else b
    if isinstance(b, Const):
        return not_(a) if b.value else a
    return Xor(a, b)


def iff_(a: Formula, b: Formula) -> Formula:
    if isinstance(a, Const):
        return b if a.value else not_(b)
    if isinstance(b, Const):
        return a if b.value else not_(a)
    return Iff(a, b)


class Pending:
    """An ``And``/``Or`` still being built by a parser from a chain of binary operators.

    Flattening ``& & & a b c d`` by copying argument tuples at each step would cost quadratic time
    on long chains; a parser instead links ``Pending`` parts and ``settle`` flattens the whole chain
    once, in linear time.
    """

    __slots__ = ("kind", "parts", "formula")

    def __init__(self, kind: type, left: object, right: object):
        self.kind = kind
        self.parts = [settle(p) if isinstance(p, Pending) and p.kind is not kind else p for p in (left, right)]
        self.formula: Formula | None = None  # ``settle``'s result, kept: a slugsin ``? i`` may settle it again

    @classmethod
    def of(cls, kind: type, parts: list) -> Pending:
        """A chain of any number of ``parts`` (the list is kept, not copied)."""
        chain = cls.__new__(cls)
        for k, p in enumerate(parts):
            if isinstance(p, Pending) and p.kind is not kind:
                parts[k] = settle(p)
        chain.kind, chain.parts, chain.formula = kind, parts, None
        return chain


def settle(x: Formula | Pending) -> Formula:
    """The formula of a parser value: a ``Pending`` chain becomes one flat ``And``/``Or``.

    The result is kept on ``x``, so a chain settled twice (an entry of a slugsin ``$`` buffer that
    ``? i`` refers to in several places) gives one shared formula, as a formula written once does.
    Nested chains are walked through their parts, never through their kept results: a buffer whose
    entries each extend the one before (``& ? i x``) settles in time linear in its size, where
    copying each entry's flat argument tuple into the next took quadratic time and memory."""
    if not isinstance(x, Pending):
        return x
    if x.formula is not None:
        return x.formula
    kind = x.kind
    out: list[Formula] = []
    stack: list = [x]
    while stack:
        item = stack.pop()
        if isinstance(item, Pending):
            stack.extend(reversed(item.parts))
        elif isinstance(item, kind):
            out.extend(item.args)
        else:
            out.append(item)
    x.formula = kind(tuple(out))
    return x.formula

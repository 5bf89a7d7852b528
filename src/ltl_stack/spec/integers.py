"""Integer variables bit-blasted the way slugs' structured-spec compiler does it.

An integer ``x:lo...hi`` is stored as the unsigned number ``x - lo`` in
``(hi - lo).bit_length()`` Boolean propositions, least significant first, named
``x@0.lo.hi``, ``x@1``, ``x@2``, … (so ``x:0...0`` has no bits at all and is always ``lo``).
When ``hi - lo + 1`` is not a power of two some bit patterns are out of range, and slugs adds
the constraint ``x - lo <= hi - lo``: for an input to ENV_INIT (unprimed) and ENV_TRANS (primed),
for an output to SYS_INIT and SYS_TRANS.

Comparisons such as ``x' + 1 = y`` are exact comparisons of natural numbers: sums get a carry bit
instead of wrapping around, so the formulas agree with slugs' on every valuation of the bits,
in range or not.

A comparison with at most two integer terms is written with a ripple-carry adder and a bitwise
comparator (a few nodes per bit). A longer sum (``x1 + x2 + … + xn = c``) would make the adder's
partial sums the problem: each is a formula of small size but a BDD of size O(i^2) for the first i
terms, so building the adder's BDD costs O(n^3). Such comparisons are compiled into a decision
diagram over the linear form ``left - right`` instead (``_diagram``): one shared node per (bit,
partial value) that can still change the outcome, so the formula is at most
``bits * (2 * terms + 1)`` nodes and its BDD is built node by node.
"""
from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import List

from ltl_stack.spec.formula import FALSE, TRUE, And, Formula, Not, Or, Var
from ltl_stack.spec.model import IntegerVariable
from ltl_stack.spec.ops import and_, conjunction, iff_, not_, or_, xor_

Bits = List[Formula]  # least significant first

_FIRST_BIT = re.compile(r"^(?P<name>.+)@0\.(?P<low>-?\d{1,18})\.(?P<high>-?\d{1,18})$")


def bit_count(low: int, high: int) -> int:
    """Number of Boolean propositions slugs uses for ``low...high``."""
    return (high - low).bit_length()


def bit_names(name: str, low: int, high: int) -> tuple[str, ...]:
    """The propositions of ``name:low...high``: ``name@0.low.high``, ``name@1``, …"""
    n = bit_count(low, high)
    return tuple(f"{name}@0.{low}.{high}" if i == 0 else f"{name}@{i}" for i in range(n))


def integer_variable(name: str, low: int, high: int) -> IntegerVariable:
    return IntegerVariable(name=name, low=low, high=high, bits=bit_names(name, low, high))


def needs_range_constraint(var: IntegerVariable) -> bool:
    """True when some bit patterns of ``var`` are above ``high``."""
    return var.high - var.low + 1 != 1 << len(var.bits)


def detect_integers(names: Sequence[str]) -> list[IntegerVariable]:
    """Integers hidden in a list of Boolean propositions compiled by slugs (``x@0.0.23``, ``x@1``, …)."""
    found = []
    position = {n: i for i, n in enumerate(names)}
    for name in names:
        m = _FIRST_BIT.match(name)
        if not m:
            continue
        var = integer_variable(m["name"], int(m["low"]), int(m["high"]))
        if not var.bits or var.bits[0] != name:
            continue
        start = position[name]
        if tuple(names[start:start + len(var.bits)]) == var.bits:
            found.append(var)
    return found


@dataclass(frozen=True)
class IntExpr:
    """A sum of bit vectors plus a constant: the value of an arithmetic expression."""

    vectors: tuple[tuple[Formula, ...], ...] = ()
    offset: int = 0

    def plus(self, other: IntExpr) -> IntExpr:
        return IntExpr(self.vectors + other.vectors, self.offset + other.offset)


def variable_expr(var: IntegerVariable, primed: bool = False) -> IntExpr:
    """``var`` (or ``var'``) as an arithmetic expression: ``low`` plus its bits."""
    return IntExpr((tuple(Var(b, primed) for b in var.bits),), var.low)


def constant_expr(value: int) -> IntExpr:
    return IntExpr((), value)


def constant_bits(value: int) -> Bits:
    if value < 0:
        raise ValueError(f"negative constant {value} has no unsigned bits")
    return [TRUE if value >> i & 1 else FALSE for i in range(value.bit_length())]


def add(a: Bits, b: Bits) -> Bits:
    """Ripple-carry sum; one bit longer than the longer operand unless the carry is constant 0."""
    out: Bits = []
    carry: Formula = FALSE
    for i in range(max(len(a), len(b))):
        x = a[i] if i < len(a) else FALSE
        y = b[i] if i < len(b) else FALSE
        half = xor_(x, y)
        out.append(xor_(half, carry))
        carry = or_(and_(x, y), and_(carry, half))
    if carry != FALSE:
        out.append(carry)
    return out


def _pad(a: Bits, n: int) -> Bits:
    return list(a) + [FALSE] * (n - len(a))


def equal(a: Bits, b: Bits) -> Formula:
    n = max(len(a), len(b))
    a, b = _pad(a, n), _pad(b, n)
    terms = [iff_(x, y) for x, y in zip(a, b)]
    if any(t == FALSE for t in terms):
        return FALSE
    return conjunction([t for t in terms if t != TRUE])


def less(a: Bits, b: Bits) -> Formula:
    """``a < b`` as unsigned numbers, decided by the most significant differing bit."""
    n = max(len(a), len(b))
    a, b = _pad(a, n), _pad(b, n)
    result: Formula = FALSE
    for x, y in zip(a, b):
        result = or_(and_(not_(x), y), and_(iff_(x, y), result))
    return result


def _vector(expr: IntExpr, extra: int) -> Bits:
    """The bits of ``expr`` with its offset replaced by ``extra`` (which must be >= 0)."""
    total: Bits = constant_bits(extra)
    for vector in expr.vectors:
        total = add(total, list(vector))
    return total


COMPARISONS = ("=", "!=", "<", "<=", ">", ">=")
#: from this many integer terms (both sides together) a comparison is compiled as a decision diagram
DIAGRAM_TERMS = 3


def compare(op: str, left: IntExpr, right: IntExpr) -> Formula:
    """``left op right`` for ``op`` in ``= != < <= > >=``, exact over the naturals."""
    if op not in COMPARISONS:
        raise ValueError(f"unknown comparison {op!r}")
    if len(left.vectors) + len(right.vectors) >= DIAGRAM_TERMS:
        return linear_comparison(op, left, right)
    shift = left.offset - right.offset
    a = _vector(left, max(shift, 0))
    b = _vector(right, max(-shift, 0))
    if op == "=":
        return equal(a, b)
    if op == "!=":
        return not_(equal(a, b))
    if op == "<":
        return less(a, b)
    if op == ">":
        return less(b, a)
    if op == "<=":
        return not_(less(b, a))
    return not_(less(a, b))


def linear_comparison(op: str, left: IntExpr, right: IntExpr) -> Formula:
    """``left op right`` as a decision diagram over the bits of ``left - right`` (see the module doc).

    The bits are tested in the order they are written (integer by integer, least significant bit
    first), which is the BDD variable order and keeps the BDD work per node small; when that order
    needs more nodes than the bound ``bits * (2 * terms + 1)`` (wide integers compared with each
    other), they are tested most significant bit first across all terms, which always meets it.
    """
    terms = [(bit, 1 << k) for vector in left.vectors for k, bit in enumerate(vector)]
    terms += [(bit, -(1 << k)) for vector in right.vectors for k, bit in enumerate(vector)]
    constant = left.offset - right.offset
    bound = len(terms) * (2 * (len(left.vectors) + len(right.vectors)) + 1) + 1
    written = _diagram(op, terms, constant, bound)
    if written is not None:
        return written
    by_weight = sorted(terms, key=lambda term: -abs(term[1]))  # stable: terms in order within a column
    result = _diagram(op, by_weight, constant, None)
    assert result is not None
    return result


def _outcome(op: str, low: int, high: int) -> Formula | None:
    """TRUE/FALSE when ``value op 0`` holds for every / no value in ``low..high``, else None."""
    if op in ("=", "!="):
        if low == high == 0:
            return TRUE if op == "=" else FALSE
        if low > 0 or high < 0:
            return FALSE if op == "=" else TRUE
        return None
    sure, never = {"<": (high < 0, low >= 0), "<=": (high <= 0, low > 0),
                   ">": (low > 0, high <= 0), ">=": (low >= 0, high < 0)}[op]
    return TRUE if sure else FALSE if never else None


def _diagram(op: str, terms: list[tuple[Formula, int]], constant: int, budget: int | None) -> Formula | None:
    """``sum(weight * bit) + constant op 0``, testing ``terms`` in order; None past ``budget`` nodes.

    Node (level, value) stands for "the terms from ``level`` on, added to ``value``, satisfy op";
    it is decided as soon as the remaining terms cannot change the outcome. Built iteratively
    (thousands of levels), each node once.
    """
    n = len(terms)
    low = [0] * (n + 1)
    high = [0] * (n + 1)
    for level in range(n - 1, -1, -1):
        weight = terms[level][1]
        low[level] = low[level + 1] + min(weight, 0)
        high[level] = high[level + 1] + max(weight, 0)
    done: dict[tuple[int, int], Formula] = {}
    stack = [(0, constant)]
    while stack:
        key = stack[-1]
        if key in done:
            stack.pop()
            continue
        level, value = key
        decided = _outcome(op, value + low[level], value + high[level])
        if decided is not None:
            done[key] = decided
            stack.pop()
            continue
        bit, weight = terms[level]
        on, off = (level + 1, value + weight), (level + 1, value)
        missing = [k for k in (on, off) if k not in done]
        if missing:
            stack.extend(missing)
            continue
        stack.pop()
        done[key] = _choice(bit, done[on], done[off])
        if budget is not None and len(done) > budget:
            return None
    return done[(0, constant)]


def _choice(bit: Formula, on: Formula, off: Formula) -> Formula:
    """``if bit then on else off`` with the constant cases folded (binary nodes: no flattening,
    which would copy argument tuples along a chain)."""
    if on is off:
        return on
    if on == TRUE:
        return bit if off == FALSE else Or((bit, off))
    if on == FALSE:
        return Not(bit) if off == TRUE else And((Not(bit), off))
    if off == TRUE:
        return Or((Not(bit), on))
    if off == FALSE:
        return And((bit, on))
    return Or((And((bit, on)), And((Not(bit), off))))


def range_constraint(var: IntegerVariable, primed: bool = False) -> Formula:
    """``var <= high`` on its bits (true for every pattern when the range is a power of two)."""
    return compare("<=", variable_expr(var, primed), constant_expr(var.high))


def range_text(var: IntegerVariable, primed: bool = False) -> str:
    """The text slugs writes for that constraint, e.g. ``0<=x'<=23``."""
    return f"{var.low}<={var.name}{chr(39) if primed else ''}<={var.high}"

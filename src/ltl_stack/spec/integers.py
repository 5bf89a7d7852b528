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
"""
from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

from ltl_stack.spec.formula import FALSE, TRUE, Formula, Var
from ltl_stack.spec.model import IntegerVariable
from ltl_stack.spec.ops import and_, conjunction, iff_, not_, or_, xor_

Bits = list[Formula]  # least significant first

_FIRST_BIT = re.compile(r"^(?P<name>.+)@0\.(?P<low>-?\d+)\.(?P<high>-?\d+)$")


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
    terms = [iff_(x, y) for x, y in zip(a, b, strict=True)]
    if any(t == FALSE for t in terms):
        return FALSE
    return conjunction([t for t in terms if t != TRUE])


def less(a: Bits, b: Bits) -> Formula:
    """``a < b`` as unsigned numbers, decided by the most significant differing bit."""
    n = max(len(a), len(b))
    a, b = _pad(a, n), _pad(b, n)
    result: Formula = FALSE
    for x, y in zip(a, b, strict=True):
        result = or_(and_(not_(x), y), and_(iff_(x, y), result))
    return result


def _vector(expr: IntExpr, extra: int) -> Bits:
    """The bits of ``expr`` with its offset replaced by ``extra`` (which must be >= 0)."""
    total: Bits = constant_bits(extra)
    for vector in expr.vectors:
        total = add(total, list(vector))
    return total


def compare(op: str, left: IntExpr, right: IntExpr) -> Formula:
    """``left op right`` for ``op`` in ``= != < <= > >=``, exact over the naturals."""
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
    if op == ">=":
        return not_(less(a, b))
    raise ValueError(f"unknown comparison {op!r}")


def range_constraint(var: IntegerVariable, primed: bool = False) -> Formula:
    """``var <= high`` on its bits (true for every pattern when the range is a power of two)."""
    return compare("<=", variable_expr(var, primed), constant_expr(var.high))


def range_text(var: IntegerVariable, primed: bool = False) -> str:
    """The text slugs writes for that constraint, e.g. ``0<=x'<=23``."""
    return f"{var.low}<={var.name}{chr(39) if primed else ''}<={var.high}"

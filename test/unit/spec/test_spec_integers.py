"""Integer comparisons: exact on every valuation (differential against Python's integers), and of a
size linear in the sum's length."""
from __future__ import annotations

import random

from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.spec import parse_structured
from ltl_stack.spec.formula import Var
from ltl_stack.spec.integers import COMPARISONS, IntExpr, _diagram, compare, linear_comparison
from ltl_stack.spec.ops import evaluate_many, size

SAMPLES = 256
MASK = (1 << SAMPLES) - 1
PYTHON = {"=": int.__eq__, "!=": int.__ne__, "<": int.__lt__, "<=": int.__le__, ">": int.__gt__, ">=": int.__ge__}


def expression(widths: list[int], offset: int, prefix: str, primed: bool = False) -> IntExpr:
    vectors = tuple(tuple(Var(f"{prefix}{k}@{i}", primed) for i in range(w)) for k, w in enumerate(widths))
    return IntExpr(vectors, offset)


def bits_of(expr: IntExpr):
    return [bit for vector in expr.vectors for bit in vector]


def value(expr: IntExpr, sample: int, values: dict[str, int]) -> int:
    return expr.offset + sum(((values[b.name] >> sample) & 1) << i for v in expr.vectors for i, b in enumerate(v))


def check_exact(formula, op: str, left: IntExpr, right: IntExpr, seed: int) -> None:
    rng = random.Random(seed)
    values = {b.name: rng.getrandbits(SAMPLES) for b in bits_of(left) + bits_of(right)}
    got = evaluate_many(formula, values, values, MASK)
    for sample in range(SAMPLES):
        expected = PYTHON[op](value(left, sample, values), value(right, sample, values))
        assert bool(got >> sample & 1) == expected, (op, left, right, sample)


sides = st.tuples(st.lists(st.integers(0, 3), max_size=4), st.integers(0, 12))


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(COMPARISONS), sides, sides, st.integers(0, 2**16))
def test_comparisons_are_exact_on_random_valuations(op, left_side, right_side, seed):
    left = expression(left_side[0], left_side[1], "a")
    right = expression(right_side[0], right_side[1], "b")
    check_exact(compare(op, left, right), op, left, right, seed)
    check_exact(linear_comparison(op, left, right), op, left, right, seed)


@settings(max_examples=100, deadline=None)
@given(st.sampled_from(COMPARISONS), sides, sides, st.integers(0, 2**16))
def test_the_most_significant_first_order_is_exact_too(op, left_side, right_side, seed):
    left = expression(left_side[0], left_side[1], "a")
    right = expression(right_side[0], right_side[1], "b")
    terms = [(b, 1 << i) for v in left.vectors for i, b in enumerate(v)]
    terms += [(b, -(1 << i)) for v in right.vectors for i, b in enumerate(v)]
    terms.sort(key=lambda t: -abs(t[1]))
    check_exact(_diagram(op, terms, left.offset - right.offset, None), op, left, right, seed)


def test_a_variable_twice_in_a_sum():
    x = IntExpr(((Var("x@0"), Var("x@1")),), 0)
    y = IntExpr(((Var("y@0"), Var("y@1"), Var("y@2")),), 0)
    twice = x.plus(x).plus(IntExpr((), 1))  # three terms: the decision diagram
    rng = random.Random(1)
    values = {n: rng.getrandbits(SAMPLES) for n in ("x@0", "x@1", "y@0", "y@1", "y@2")}
    got = evaluate_many(compare("=", twice, y), values, values, MASK)
    for s in range(SAMPLES):
        xv = (values["x@0"] >> s & 1) + 2 * (values["x@1"] >> s & 1)
        yv = sum((values[f"y@{i}"] >> s & 1) << i for i in range(3))
        assert bool(got >> s & 1) == (2 * xv + 1 == yv), s


def sum_spec(n: int, total: int) -> str:
    declarations = "\n".join(f"x{k}:0...7" for k in range(n))
    return f"[INPUT]\n{declarations}\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n" + \
        " + ".join(f"x{k}" for k in range(n)) + f" = {total} -> y'\n"


def test_a_long_sum_is_linear_in_its_length():
    sizes = [size(parse_structured(sum_spec(n, 5)).sys_safety[0].formula) for n in (50, 100, 200)]
    assert sizes[1] <= 2.2 * sizes[0] and sizes[2] <= 2.2 * sizes[1], sizes


@settings(max_examples=40, deadline=None)
@given(st.integers(3, 40), st.integers(0, 400), st.sampled_from(COMPARISONS))
def test_diagram_size_stays_within_its_bound(n, total, op):
    left = expression([3] * n, 0, "x")
    right = IntExpr((), total)
    bits = 3 * n
    # the module's bound is bits * (2n + 1) diagram nodes; a node is at most four formula objects
    # (Or, two Ands, the Not of its bit), and the bits and two constants come on top
    nodes = size(compare(op, left, right))  # (a failing assert does not print the whole formula)
    assert nodes <= 4 * bits * (2 * n + 1) + bits + 2, (n, total, op)


def test_wide_integers_compared_with_each_other_stay_small():
    # in the written order x + y = z would need 2^20 nodes; most significant bit first needs a few per bit
    x, y, z = (expression([20], 0, name) for name in ("x", "y", "z"))
    formula = compare("=", x.plus(y), z)
    assert size(formula) <= 60 * 7 * 4, size(formula)
    check_exact(formula, "=", x.plus(y), z, seed=3)

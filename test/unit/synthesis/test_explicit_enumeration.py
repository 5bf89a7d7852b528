"""The enumeration helpers of explicit extraction against dd's own answers: integer codes of a
BDD's valuations (results of shared nodes kept across BDDs) and restrictions cached by the values
of only the variables a BDD depends on."""
from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.synthesis.explicit import _Codes, _Restricted
from ltl_stack.synthesis.game import new_manager

NAMES = [f"v{i}" for i in range(6)]

#: a random Boolean function as a DNF: terms of (variable index, sign) literals
dnfs = st.lists(st.lists(st.tuples(st.integers(0, 5), st.booleans()), max_size=4), max_size=5)


def _bdd_of(bdd, dnf):
    u = bdd.false
    for term in dnf:
        t = bdd.true
        for k, sign in term:
            t &= bdd.var(NAMES[k]) if sign else ~bdd.var(NAMES[k])
        u |= t
    return u


def _manager(order: list[int]):
    bdd = new_manager(2**28)
    bdd.declare(*[NAMES[k] for k in order])
    bdd.configure(reordering=False)
    return bdd


@settings(max_examples=80, deadline=None)
@given(st.lists(dnfs, min_size=1, max_size=4), st.permutations(range(6)), st.permutations(range(6)))
def test_codes_are_the_valuations_even_with_nodes_shared_across_bdds(functions, order, bits) -> None:
    bdd = _manager(list(order))
    bit_of = {NAMES[k]: b for k, b in zip(range(6), bits)}
    codes = _Codes(bdd, bit_of)
    for dnf in functions:  # one enumerator for all: later BDDs re-use the kept results
        u = _bdd_of(bdd, dnf)
        expected = sorted(sum(1 << bit_of[v] for v, val in a.items() if val)
                          for a in bdd.pick_iter(u, care_vars=set(NAMES)))
        got = codes(u)
        assert sorted(got) == expected
        assert len(got) == len(set(got))  # each valuation once


@settings(max_examples=80, deadline=None)
@given(dnfs, st.permutations(range(6)), st.integers(0, 2**6 - 1), st.integers(0, 2**6 - 1), st.booleans())
def test_restriction_cached_by_the_support_equals_the_full_restriction(dnf, order, first, second, truth) -> None:
    bdd = _manager(list(order))
    # v4 and v5 stay free (next-state-like variables): only v0..v3 are positions' bits
    current_bit = {NAMES[k]: k for k in range(4)}
    u = _bdd_of(bdd, dnf)
    restricted = _Restricted(bdd, u, current_bit, truth=truth)
    for code in (first, second, first):  # the second look-up of ``first`` comes from the cache
        full = bdd.let({v: bool(code >> k & 1) for v, k in current_bit.items()}, u)
        assert restricted(code) == ((full == bdd.true) if truth else full)

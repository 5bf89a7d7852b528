"""Game construction for specs with thousands of propositions: the variable order the
game declares, n-ary conjunctions combined as balanced trees, and verdicts of a scalable family."""
from __future__ import annotations

import functools
import operator
import sys
import warnings

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.spec import parse_slugsin
from ltl_stack.synthesis import Game, relation, synthesize
from ltl_stack.synthesis.game import BALANCED_FROM, REORDER_MAX_VARIABLES, _balanced, new_manager


def scaled_spec(n: int, toggle: bool = True) -> str:
    """n inputs that stay on once on, n outputs that toggle (or keep their value), one goal."""
    def conj(parts: list[str]) -> str:
        return " ".join(["&"] * (len(parts) - 1) + parts)

    xs, ys = [f"x{i}" for i in range(n)], [f"y{i}" for i in range(n)]
    step = "^ {y}' {y}" if toggle else "! ^ {y}' {y}"
    return "\n".join(["[INPUT]", *xs, "[OUTPUT]", *ys,
                      "[ENV_TRANS]", conj([f"| ! {x} {x}'" for x in xs]),
                      "[SYS_INIT]", conj([f"! {y}" for y in ys]),
                      "[SYS_TRANS]", conj([step.format(y=y) for y in ys]),
                      "[SYS_LIVENESS]", "y0", ""])


def test_variables_are_declared_interleaved_in_spec_order() -> None:
    game = Game(parse_slugsin(scaled_spec(3)), interleave=True)
    levels = [game.bdd.var_at_level(i) for i in range(12)]
    assert levels == ["x0", "x0'", "x1", "x1'", "x2", "x2'", "y0", "y0'", "y1", "y1'", "y2", "y2'"]
    block = Game(parse_slugsin(scaled_spec(2)), interleave=False)
    assert [block.bdd.var_at_level(i) for i in range(8)] == ["x0", "x1", "y0", "y1", "x0'", "x1'", "y0'", "y1'"]


def test_big_games_neither_reorder_nor_race_and_keep_their_verdict() -> None:
    n = REORDER_MAX_VARIABLES // 2  # 2n propositions, 4n BDD variables
    for toggle, verdict in ((True, True), (False, False)):
        spec = parse_slugsin(scaled_spec(n, toggle))
        result = synthesize(spec)
        assert result.realizable is verdict
        assert not result.game.may_reorder and result.game.interleave
        assert result.game.bdd.configure()["reordering"] is False


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 5), st.booleans()), min_size=0, max_size=3 * BALANCED_FROM),
       st.booleans())
def test_balanced_combination_equals_the_chain(literals, conjunction) -> None:
    bdd = new_manager(2**28)
    bdd.declare(*[f"v{i}" for i in range(6)])
    vals = [bdd.var(f"v{a}") | (bdd.var(f"v{b}") if sign else ~bdd.var(f"v{b}")) for a, b, sign in literals]
    unit, op = (bdd.true, operator.and_) if conjunction else (bdd.false, operator.or_)
    assert _balanced(list(vals), unit, op) == functools.reduce(op, vals, unit)


def _game_work(n: int) -> tuple[int, float]:
    """(Python calls, CUDD cache lookups) to build the game of ``scaled_spec(n)``: counts, not times."""
    spec = parse_slugsin(scaled_spec(n))
    calls = 0

    def profile(frame, event, arg) -> None:
        nonlocal calls
        calls += event in ("call", "c_call")

    sys.setprofile(profile)
    try:
        game = Game(spec)
    finally:
        sys.setprofile(None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # dd warns that one unrelated key changed its unit
        return calls, game.bdd.statistics()["cache_lookups"]


@pytest.mark.parametrize("whole_nodes", [0, 10 ** 9], ids=["partitioned", "whole"])
def test_doubling_the_propositions_doubles_the_game_construction_work(whole_nodes, monkeypatch) -> None:
    # each clause is one n-ary conjunction over all propositions: balanced combination makes the BDD
    # work n log n (a chain was quadratic); the Python side is linear (declaration, to_bdd). A safety
    # section is kept whole below relation.WHOLE_NODES and scheduled into clusters above it: each way
    # is measured on its own (a pair of sizes on both sides of the limit adds the scheduling once)
    monkeypatch.setattr(relation, "WHOLE_NODES", whole_nodes)
    for n in (300, 1200):
        (calls, lookups), (calls2, lookups2) = _game_work(n), _game_work(2 * n)
        assert 1.8 < calls2 / calls < 2.2, (n, calls, calls2)
        assert 1.8 < lookups2 / lookups < 2.5, (n, lookups, lookups2)

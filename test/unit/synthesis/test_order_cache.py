"""Variable orders reused between runs (``ltl_stack.synthesis.order_cache``): counted, not timed."""
from __future__ import annotations

import warnings

import pytest
from helpers import needs_cudd

from ltl_stack.spec.slugsin import parse_slugsin
from ltl_stack.synthesis import Game, order_cache, synthesize

K = 12


def crossed_spec(goal: str = "| y0 ! y0"):
    """y_i' = y_i xor x_(K-1-i)': in the declared order (all inputs above all outputs) the relation
    needs 2^K nodes, so CUDD sifts while building it; in the sifted order it is linear."""
    xs, ys = [f"x{i}" for i in range(K)], [f"y{i}" for i in range(K)]
    lines = ["[INPUT]", *xs, "[OUTPUT]", *ys, "[SYS_TRANS]"]
    lines += [f"! ^ y{i}' ^ y{i} x{K - 1 - i}'" for i in range(K)]
    lines += ["[SYS_LIVENESS]", goal]
    return parse_slugsin("\n".join(lines) + "\n")


def reorderings(game: Game) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return game.bdd.statistics()["n_reorderings"]


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "orders"
    monkeypatch.setenv("LTL_STACK_ORDER_CACHE", str(folder))
    return folder


@needs_cudd
def test_a_second_run_of_the_same_spec_reorders_zero_times(cache):
    spec = crossed_spec()
    first = synthesize(spec)
    assert reorderings(first.game) >= 1 and first.game.order_reused is None
    second = synthesize(spec)
    assert second.game.order_reused == "exact"
    assert reorderings(second.game) == 0
    assert second.realizable == first.realizable
    assert second.game.count(second.solution.winning) == first.game.count(first.solution.winning)


@needs_cudd
def test_a_variant_with_the_same_propositions_starts_in_the_saved_order(cache):
    synthesize(crossed_spec())
    variant = Game(crossed_spec(goal="| y1 ! y1"))
    assert variant.order_reused == "propositions"
    assert variant.may_reorder  # only a start: sifting stays on for a spec it was not found for


def test_the_cache_is_bounded_and_can_be_switched_off(cache, monkeypatch):
    monkeypatch.setattr(order_cache, "MAX_ENTRIES", 3)
    for goal in ("y0", "y1", "y2", "y3"):
        order_cache.save(crossed_spec(goal), ["a", "b"])
    assert len(list(cache.glob("*.json"))) == 3
    monkeypatch.setenv("LTL_STACK_ORDER_CACHE", "off")
    assert order_cache.cache_dir() is None
    game = synthesize(crossed_spec()).game
    assert game.order_reused is None and not (cache / f"{order_cache.keys(crossed_spec())[0]}.json").exists()


def test_a_broken_or_foreign_entry_is_ignored(cache):
    spec = crossed_spec()
    cache.mkdir()
    content, names = order_cache.keys(spec)
    (cache / f"{content}.json").write_text("{not json")
    (cache / f"{names}.json").write_text('["x0", "nope"]')
    game = Game(spec)
    assert game.order_reused is None

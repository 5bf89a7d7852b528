"""Hand-checkable cases for the BDD game, the fixpoints of Eq. 4.2 and both init semantics.

Each spec is small enough that the expected verdict or set is argued in its comment.
"""
from __future__ import annotations

import itertools

import pytest
from random_specs import make_spec

from ltl_stack.synthesis import Game, Options, is_realizable, synthesize
from ltl_stack.synthesis.fixpoint import solve


def verdicts(spec):
    """(default init semantics, robotics init semantics)."""
    return (is_realizable(spec, robotics_semantics=False), is_realizable(spec, robotics_semantics=True))


def winning_valuations(game: Game, winning) -> set[tuple[int, ...]]:
    names = game.variables
    got = set()
    for a in game.bdd.pick_iter(winning, care_vars=set(names)):
        got.add(tuple(int(a[n]) for n in names))
    return got


def test_game_api_names_and_priming():
    game = Game(make_spec(["i"], ["o"], sys_safety=["! ^ o' i'"]))
    assert (game.inputs, game.outputs, game.inputs_next, game.outputs_next) == \
        (["i"], ["o"], ["i'"], ["o'"])
    bdd = game.bdd
    assert game.prime(bdd.var("i") & ~bdd.var("o")) == bdd.var("i'") & ~bdd.var("o'")
    assert game.unprime(bdd.var("o'")) == bdd.var("o")
    # interleaved order: each variable next to its primed copy
    levels = [bdd.level_of_var(v) for v in ["i", "i'", "o", "o'"]]
    assert levels == [0, 1, 2, 3], levels
    # empty liveness sections become one true goal
    assert (len(game.env_goals), len(game.sys_goals)) == (1, 1)
    assert game.env_goals[0] == bdd.true


def test_cpre_sys_is_mealy_and_env_violation_wins():
    # sys must copy the next input: possible from everywhere because it sees i' first.
    game = Game(make_spec(["i"], ["o"], sys_safety=["! ^ o' i'"]))
    assert game.cpre_sys(game.true) == game.true
    # predicting the next input with the current output is impossible ...
    game = Game(make_spec(["i"], ["o"], sys_safety=["! ^ o i'"]))
    assert game.cpre_sys(game.true) == game.false
    # ... unless env safety forbids the next input to change: then exactly o == i positions win
    game = Game(make_spec(["i"], ["o"], sys_safety=["! ^ o i'"], env_safety=["! ^ i i'"]))
    got = winning_valuations(game, game.cpre_sys(game.true))
    assert got == {(0, 0), (1, 1)}, got


def test_cpre_env_is_the_dual():
    game = Game(make_spec(["i"], ["o"], sys_safety=["! ^ o i'"], env_safety=["! ^ i i'"]))
    bdd = game.bdd
    target = game.prime(bdd.var("o"))  # the environment wants o' true
    # env cannot force o' (sys may keep choosing freely), except where sys cannot move at all
    forced = game.cpre_env(target)
    assert winning_valuations(game, forced) == {(0, 1), (1, 0)}, winning_valuations(game, forced)


def test_clause_bdds_and_violated():
    spec = make_spec(["i"], ["o"], env_safety=["| ! i ! i'", "1"])
    game = Game(spec)
    clauses = game.clauses("env_safety")
    assert [c.text for c, _ in clauses] == ["| ! i ! i'", "1"], clauses
    got = [c.text for c in game.violated("env_safety", {"i": True, "o": False}, {"i": True})]
    assert got == ["| ! i ! i'"], got


@pytest.mark.parametrize("name, sections, expected", [
    ("no constraints", {}, (True, True)),
    # positions with o true have no allowed move: W = {o false}. Default semantics lets the
    # robot start with o false; robotics semantics also requires the o-true start to win.
    ("some initial positions lose", dict(sys_safety=["! o"]), (True, False)),
    # sys_init pins o true: losing in both semantics.
    ("sys_init picks a losing position", dict(sys_safety=["! o"], sys_init=["o"]), (False, False)),
    # env_init restricts the start to i false; o must equal i initially and o must be false:
    # both semantics fine since the only admissible start is (i=0, o=0).
    ("env_init narrows the start", dict(env_init=["! i"], sys_init=["! ^ o i"], sys_safety=["! o"]),
     (True, True)),
    # default semantics: for i=1 the robot needs o=1 (sys_init), which loses.
    ("default needs a good output per input", dict(sys_init=["! ^ o i"], sys_safety=["! o"]),
     (False, False)),
    # sys violates nothing when the env cannot move at all
    ("env safety false", dict(env_safety=["0"], sys_safety=["0"]), (True, True)),
])
def test_init_semantics(name, sections, expected):
    got = verdicts(make_spec(["i"], ["o"], **sections))
    assert got == expected, (name, got)


def test_liveness_with_primes_needs_the_env_assumption():
    # goal: a rising edge of o (a transition property); o may only rise when i' holds.
    sections = dict(sys_safety=["| ! & ! o o' i'"], sys_liveness=["& ! o o'"])
    assert verdicts(make_spec(["i"], ["o"], **sections)) == (False, False)
    # with "infinitely often i" the robot waits for i and rises then
    with_assumption = make_spec(["i"], ["o"], env_liveness=["i"], **sections)
    assert verdicts(with_assumption) == (True, True)
    # an assumption that is a transition too: i rises infinitely often
    rising = make_spec(["i"], ["o"], env_liveness=["& ! i i'"], **sections)
    assert verdicts(rising) == (True, True)


def test_two_goals_must_both_be_reachable():
    # o can only become true when i' holds; goals "o" and "! o"; env assumption GF i.
    spec = make_spec(["i"], ["o"], sys_safety=["| ! o' | o i'"], sys_liveness=["o", "! o"],
                     env_liveness=["i"])
    assert verdicts(spec) == (True, True)
    # without the assumption the env keeps i false and "o" is never reached
    spec = make_spec(["i"], ["o"], sys_safety=["| ! o' | o i'"], sys_liveness=["o", "! o"])
    assert verdicts(spec) == (False, False)


def test_techniques_do_not_change_the_winning_set():
    spec = make_spec(["i", "j"], ["o", "p"], env_safety=["| ! i ! i'"],
                     sys_safety=["| ! o' | o i'", "| ! p' j'"],
                     sys_liveness=["o", "& p ! o"], env_liveness=["i", "j"])
    results = set()
    for recycle, reorder, gauss_seidel in itertools.product((True, False), repeat=3):
        game = Game(spec)
        options = Options(recycle=recycle, reorder=reorder, gauss_seidel=gauss_seidel)
        sol = solve(game, options=options)
        results.add((sol.realizable, frozenset(winning_valuations(game, sol.winning))))
    assert len(results) == 1, results
    realizable, winning = results.pop()
    assert realizable, winning


def test_gauss_seidel_rounds_need_fewer_cpre_calls_for_the_same_winning_set():
    """The benchmark's grid patrol with two obstacles (four liveness assumptions): computing each
    X with the Y already grown in the same round must save cpre calls, not just time."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_synthesis_family.py"
    module_spec = importlib.util.spec_from_file_location("bench_synthesis_family", path)
    family = importlib.util.module_from_spec(module_spec)
    module_spec.loader.exec_module(family)
    spec = family.grid_patrol(8, 4, 2)
    results = {}
    for gauss_seidel in (True, False):
        game = Game(spec)
        calls = []
        cpre = game.cpre_sys
        game.cpre_sys = lambda target, trans=None, cpre=cpre, calls=calls: calls.append(1) or cpre(target, trans)
        # in CUDD throughout: a long fixpoint moves to oxidd after a warm-up, past the counting wrapper
        sol = solve(game, options=Options(gauss_seidel=gauss_seidel, kernel="cudd"))
        results[gauss_seidel] = (len(calls), sol.realizable, frozenset(winning_valuations(game, sol.winning)))
    (fast, *same_fast), (slow, *same_slow) = results[True], results[False]
    assert same_fast == same_slow
    assert fast < 0.8 * slow, (fast, slow)


def test_early_exit_stops_before_the_fixpoint():
    spec = make_spec(["i"], ["o"], sys_init=["o"], sys_safety=["| ! o' | o i'"],
                     sys_liveness=["o", "! o"])
    game = Game(spec)
    full = solve(game)
    early = solve(Game(spec), early_exit=True)
    assert (full.realizable, early.realizable, early.complete) == (False, False, False)


def test_synthesize_reports_unrealizable_without_strategy():
    result = synthesize(make_spec(["i"], ["o"], sys_safety=["0"]))
    assert (result.realizable, result.strategy) == (False, None)
    assert result.seconds >= 0


def test_cooperation_traps_the_environment_only_as_a_last_resort():
    # Env safety "! o": once o is true the environment has no admissible move, so the robot
    # "wins" the impossible goal (false) by setting o. It starts with o false (sys_init).
    # The cooperative game is lost; the verdict stays the spec's, and the strategy says it is
    # not fully cooperative.
    spec = make_spec(["i"], ["o"], sys_init=["! o"], env_safety=["! o"], sys_liveness=["0"])
    game = Game(spec)
    got = (solve(game).realizable, solve(game, cooperative=True).realizable)
    assert got == (True, False), got
    result = synthesize(spec, robotics_semantics=False, cooperative=True)
    assert (result.realizable, result.strategy.fully_cooperative) == (True, False)
    state = result.strategy.step(result.strategy.initial_state({"i": False}), {"i": True})
    assert state.outputs == {"o": True}, state.outputs
    # when both o values are fine, the cooperative strategy leaves the environment a move
    fine = make_spec(["i"], ["o"], env_safety=["! o"])
    strategy = synthesize(fine, cooperative=True).strategy
    assert strategy.fully_cooperative
    state = strategy.initial_state({"i": False}, {"o": False})
    for value in (True, False, True):
        state = strategy.step(state, {"i": value})
        assert state.outputs == {"o": False}, state.outputs

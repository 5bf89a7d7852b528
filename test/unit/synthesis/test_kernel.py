"""The oxidd fixpoint kernel (``ltl_stack.synthesis.kernel``) against the CUDD engine.

Every game here is solved twice on the same ``Game``: in CUDD and in oxidd (forced with
``Options(kernel=...)`` or ``LTL_STACK_KERNEL``, or chosen by the warm-up). The oxidd solution is
copied back into the game's CUDD manager, so the winning region and every iterate the strategy reads
must be the very same BDDs; verdicts, explicit automata, recovery automata and explanations must be
equal, and strategies must model-check. No timing is asserted anywhere.
"""
from __future__ import annotations

import pytest
from helpers import require_shared
from hypothesis import given, settings
from hypothesis import strategies as st
from random_specs import make_spec, random_spec

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import kernel, synthesize
from ltl_stack.synthesis.automaton_check import check_automaton
from ltl_stack.synthesis.fixpoint import Options, solve
from ltl_stack.synthesis.game import BACKEND, Game, backend_line

needs_oxidd = pytest.mark.skipif(BACKEND != "cudd" or not kernel.available(),
                                 reason="oxidd (CPython >= 3.9) and dd.cudd are needed for the second kernel")

CUDD = Options(kernel="cudd")
OXIDD = Options(kernel="oxidd")

#: a game whose fixpoint takes a few dozen controllable predecessors (a 3-bit counter that counts up
#: while the environment's r is off and holds while it is on; r is off infinitely often; the counter must
#: reach 7 infinitely often)
COUNTER = make_spec(
    ["r"], ["b0", "b1", "b2"],
    env_liveness=["! r"],
    sys_init=["! b0", "! b1", "! b2"],
    sys_safety=["| ! r' & ! ^ b0' b0 & ! ^ b1' b1 ! ^ b2' b2",
                "| r' ! ^ b0' ! b0",
                "| r' ! ^ b1' ^ b1 b0",
                "| r' ! ^ b2' ^ b2 & b1 b0"],
    sys_liveness=["& b0 & b1 b2"],
)


def assert_same_solution(got, want) -> None:
    """Same verdict, same winning BDD, same iterates (both in the game's CUDD manager)."""
    assert got.realizable == want.realizable
    assert got.complete == want.complete
    assert got.winning == want.winning
    assert got.z_iterations == want.z_iterations
    assert [gl.Y for gl in got.layers] == [gl.Y for gl in want.layers]
    assert [gl.X for gl in got.layers] == [gl.X for gl in want.layers]
    assert got.cpre_winning == want.cpre_winning


@needs_oxidd
@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10**6), robotics=st.booleans(), cooperative=st.booleans(), early=st.booleans())
def test_oxidd_and_cudd_solve_random_games_alike(seed, robotics, cooperative, early):
    game = Game(random_spec(seed))
    want = solve(game, robotics_semantics=robotics, cooperative=cooperative, early_exit=early, options=CUDD)
    got = solve(game, robotics_semantics=robotics, cooperative=cooperative, early_exit=early, options=OXIDD)
    assert (want.kernel, got.kernel) == ("cudd", "oxidd")
    assert_same_solution(got, want)


SHARED_SPECS = [
    "slugsin/firefighting", "slugsin/two_customer_waiter_txt", "slugsin/fastslow__fastslow_ICRA",
    "slugsin/error_resilience_exampleA", "slugsin/unrealizable_waiter_txt", "slugsin/networks",
    "generated/factory_assembly_4x3_1_1errors", "generated/factory_assembly_5x3_1_4errors",
    "generated/moving_obstacle_8x8_1glitches", "generated/cinderella_stepmother_n5c2_6_by_4",
]


@needs_oxidd
@pytest.mark.parametrize("name", SHARED_SPECS)
def test_oxidd_and_cudd_solve_the_shared_specs_alike(name):
    game = Game(load_spec(require_shared("specs", "benchmarks", f"{name}.slugsin")))
    for robotics in (False, True):
        want = solve(game, robotics_semantics=robotics, options=CUDD)
        got = solve(game, robotics_semantics=robotics, options=OXIDD)
        assert got.kernel == "oxidd"
        assert_same_solution(got, want)


@needs_oxidd
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_strategies_solved_in_oxidd_model_check_and_export_as_in_cudd(seed):
    spec = random_spec(seed)
    want = synthesize(spec, robotics_semantics=False, options=CUDD)
    got = synthesize(spec, robotics_semantics=False, options=OXIDD)
    assert got.realizable == want.realizable
    if got.strategy is None:
        return
    assert got.solution.kernel == "oxidd"
    automaton = got.strategy.explicit(max_states=5_000)
    check_automaton(automaton, spec)
    assert automaton.to_json() == want.strategy.explicit(max_states=5_000).to_json()
    recovery = got.strategy.explicit(max_states=5_000, recovery=True)
    check_automaton(recovery, spec)
    assert recovery.to_json() == want.strategy.explicit(max_states=5_000, recovery=True).to_json()


@needs_oxidd
@pytest.mark.parametrize("name", ["slugsin/unrealizable_waiter_txt", "slugsin/firefighting"])
def test_explain_answers_alike_whichever_kernel_solved(name, monkeypatch):
    from ltl_stack.synthesis.explain import explain
    from ltl_stack.synthesis.explain_render import explanation_dict

    spec = load_spec(require_shared("specs", "benchmarks", f"{name}.slugsin"))
    monkeypatch.setenv(kernel.KERNEL_ENV, "cudd")
    want = explanation_dict(explain(spec, counterstrategy=True))
    monkeypatch.setenv(kernel.KERNEL_ENV, "oxidd")
    got = explanation_dict(explain(spec, counterstrategy=True))
    assert got == want


@needs_oxidd
def test_auto_keeps_a_short_fixpoint_in_cudd_and_moves_a_long_one_to_oxidd(monkeypatch):
    game = Game(COUNTER)
    want = solve(game, options=CUDD)
    assert want.realizable
    short = solve(game, options=Options(kernel="auto"))
    assert short.kernel == "cudd"  # it ends within the warm-up
    monkeypatch.setattr(kernel, "WARMUP_CPRE", 3)
    messages: list[str] = []
    long = solve(game, options=Options(kernel="auto"), progress=messages.append)
    assert long.kernel == "oxidd", messages
    assert any("fixpoint in oxidd" in m for m in messages), messages
    assert_same_solution(long, want)


@needs_oxidd
def test_oxidd_out_of_memory_falls_back_to_cudd_with_the_same_answer(monkeypatch):
    game = Game(COUNTER)
    want = solve(game, options=CUDD)
    monkeypatch.setattr(kernel, "capacity", lambda max_memory: (8, 64))  # far too few nodes
    messages: list[str] = []
    got = solve(game, options=OXIDD, progress=messages.append)
    assert got.kernel == "cudd"
    assert any("oxidd ran out of its memory share" in m for m in messages), messages
    assert_same_solution(got, want)


def test_without_oxidd_every_game_is_solved_in_cudd(monkeypatch):
    monkeypatch.setattr(kernel, "_AVAILABLE", [False])
    game = Game(COUNTER)
    assert solve(game, options=OXIDD).kernel == "cudd"
    assert "oxidd not installed" in kernel.describe("auto")


def test_the_backend_line_names_the_kernel(monkeypatch):
    monkeypatch.setenv(kernel.KERNEL_ENV, "cudd")
    assert "fixpoints in CUDD" in backend_line() or BACKEND != "cudd"
    if BACKEND == "cudd" and kernel.available():
        monkeypatch.setenv(kernel.KERNEL_ENV, "auto")
        assert "oxidd" in backend_line()


def test_an_unknown_kernel_is_refused_in_one_line():
    with pytest.raises(ValueError, match="unknown BDD kernel 'fast'"):
        solve(Game(COUNTER), options=Options(kernel="fast"))

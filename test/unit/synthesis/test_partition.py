"""Partitioned transition relations (``ltl_stack.synthesis.relation``) against the monolithic engine.

With ``CLUSTER_NODES`` lowered to 1 every safety clause is a cluster of its own (the most partitioned
the engine can be); ``Game(partition=False)`` is the engine with one BDD per safety section, conjoined
in file order. Both must give the same winning positions and verdicts; the partitioned fixpoint must
never build the single ``env_trans`` BDD; its strategies must model-check.
"""
from __future__ import annotations

from contextlib import contextmanager

import pytest
from helpers import require_shared
from hypothesis import given, settings
from hypothesis import strategies as st
from random_specs import make_spec, random_spec

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import relation, synthesize
from ltl_stack.synthesis.automaton_check import check_automaton
from ltl_stack.synthesis.fixpoint import solve
from ltl_stack.synthesis.game import Game
from ltl_stack.synthesis.relation import Relation, schedule


@contextmanager
def clusters_of(nodes: int):
    """Every relation built inside is clustered up to ``nodes`` nodes (and kept whole only up to that)."""
    old = relation.CLUSTER_NODES, relation.WHOLE_NODES
    relation.CLUSTER_NODES = relation.WHOLE_NODES = nodes
    try:
        yield
    finally:
        relation.CLUSTER_NODES, relation.WHOLE_NODES = old


def valuations(game: Game, u) -> set[tuple[bool, ...]]:
    """The valuations of the current variables in ``u`` (comparable across managers)."""
    return {tuple(bool(a[v]) for v in game.variables)
            for a in game.bdd.pick_iter(u, care_vars=set(game.variables))}


def test_schedule_takes_the_least_shared_variables_first_not_the_file_order():
    supports = [{"a'", "b'"}, {"a'"}, {"c'"}, {"x"}]
    got = schedule(supports, ["a'", "b'", "c'"])
    # x mentions no quantified variable: first; then b' (1 clause), c' (1 clause), a' (2 clauses)
    assert got == [3, 0, 2, 1], got


def test_quantification_per_cluster_equals_quantifying_the_conjunction():
    spec = make_spec(["a", "b"], ["x", "y"],
                     env_safety=["| ! a b'", "| a' ! b'", "| x a'"],
                     sys_safety=["| ! x' y'", "| a' x'", "^ y' b'"])
    with clusters_of(1):
        game = Game(spec)
    for rel, q in ((game.env_rel, game.inputs_next), (game.sys_rel, game.outputs_next),
                   (game.sys_rel, game.variables_next)):
        assert len(rel.parts) == 3, rel.parts
        whole = rel.conjunction()
        for target in (game.true, game.bdd.var("y'"), game.bdd.var("a") | ~game.bdd.var("x'")):
            assert rel.exist_and(target, q) == game.bdd.exist(q, whole & target)
            assert rel.forall_implies(target, q) == game.bdd.forall(q, ~whole | target)


def test_the_fixpoint_and_the_strategy_never_build_the_single_env_trans():
    spec = make_spec(["a", "b"], ["x", "y"], env_init=["! a"], env_safety=["| ! a b'", "| a' ! b'", "| x a'"],
                     env_liveness=["a"], sys_safety=["| ! x' y'", "| a' x'", "| ! b' y'"], sys_liveness=["x"])
    with clusters_of(1):
        result = synthesize(spec, robotics_semantics=False)
        assert result.realizable
        result.strategy.explicit(recovery=True)
        state = result.strategy.initial_state()
        result.strategy.step(state, {"a": True, "b": True})
    game = result.game
    assert len(game.env_rel.parts) > 1, game.env_rel.parts
    assert game.env_rel.built == 0
    assert game.sys_rel.built == 0
    whole = game.env_trans  # on demand only
    assert game.env_rel.built == 1 and whole == game.env_rel.conjoin(game.true)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10**6), robotics=st.booleans(), cooperative=st.booleans())
def test_partitioned_and_monolithic_engines_agree(seed, robotics, cooperative):
    spec = random_spec(seed)
    mono = Game(spec, partition=False)
    with clusters_of(1):
        part = Game(spec)
        got = solve(part, robotics_semantics=robotics, cooperative=cooperative)
    want = solve(mono, robotics_semantics=robotics, cooperative=cooperative)
    assert got.realizable == want.realizable, (seed, robotics, cooperative)
    assert valuations(part, got.winning) == valuations(mono, want.winning), seed
    assert part.env_rel.built == 0


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_partitioned_strategies_model_check(seed):
    spec = random_spec(seed)
    with clusters_of(1):
        result = synthesize(spec, robotics_semantics=False)
        if result.strategy is None:
            return
        check_automaton(result.strategy.explicit(max_states=5_000), spec)
        check_automaton(result.strategy.explicit(max_states=5_000, recovery=True), spec)


def test_a_relation_small_in_file_order_stays_one_bdd():
    spec = make_spec(["a"], ["x"], env_safety=["| ! a a'", "| a' ! a"], sys_safety=["| x' a'"])
    game = Game(spec)
    assert len(game.env_rel.parts) == 1 and len(game.sys_rel.parts) == 1
    assert isinstance(game.env_rel, Relation)


SHARED_SPECS = [
    "slugsin/firefighting", "slugsin/two_customer_waiter_txt", "slugsin/fastslow__fastslow_ICRA",
    "slugsin/error_resilience_exampleA", "slugsin/unrealizable_waiter_txt", "slugsin/networks",
    "generated/factory_assembly_4x3_1_1errors", "generated/factory_assembly_5x3_1_4errors",
    "generated/factory_assembly_5x4_1_0errors", "generated/moving_obstacle_8x8_1glitches",
    "generated/cinderella_stepmother_n5c2_6_by_4",
]


@pytest.mark.parametrize("name", SHARED_SPECS)
def test_partitioned_and_monolithic_engines_agree_on_the_shared_specs(name):
    spec = load_spec(require_shared("specs", "benchmarks", f"{name}.slugsin"))
    mono = Game(spec, partition=False)
    with clusters_of(200):  # several clusters even where the default keeps one
        part = Game(spec)
    for robotics in (False, True):
        got = solve(part, robotics_semantics=robotics)
        want = solve(mono, robotics_semantics=robotics)
        assert got.realizable == want.realizable, (name, robotics)
        assert part.count(got.winning) == mono.count(want.winning), (name, robotics)
    assert part.env_rel.built == 0 and part.sys_rel.built == 0


def test_the_vacuity_check_never_builds_the_single_relations():
    """The check after the verdict goes through the same partitioned predecessors as the solve, in
    both of its questions (together with the robot's safety, and the environment alone)."""
    from ltl_stack.synthesis import vacuity

    spec = make_spec(["a", "b"], ["x", "y"], env_init=["! a"], env_safety=["| ! a b'", "| a' ! b'", "| x a'"],
                     env_liveness=["a"], sys_safety=["| ! x' y'", "| a' x'", "| ! b' y'"], sys_liveness=["x"])
    with clusters_of(1):
        result = synthesize(spec, robotics_semantics=False, strategy=False)
        game = result.game
        counts = vacuity.Counts()
        joint = vacuity.check(game, result.solution.winning, counts=counts)
        assert joint.assumptions_satisfiable
        never = make_spec(["done"], ["act"], env_safety=["| act ! done'"], env_liveness=["& act done"],
                          sys_safety=["| ! done' ! act'"], sys_liveness=["act"])
        alone = synthesize(never, robotics_semantics=False, strategy=False)
        vacuity.check(alone.game, alone.solution.winning)
    assert len(game.env_rel.parts) > 1 and counts.pres > 0
    for g in (game, alone.game):
        assert g.env_rel.built == 0 and g.sys_rel.built == 0

"""Mutual-exclusion suggestions: semantics for any number of propositions, merging, spec edits."""
from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.analysis.suggest import (
    ENVIRONMENT,
    MutualExclusion,
    add_to_spec,
    input_exclusion_for,
    mark_guaranteed,
    mutual_exclusions,
)
from ltl_stack.spec.formula import And, Not, Or, Var, evaluate, variables
from ltl_stack.spec.model import Clause, Spec

prop_names = st.lists(st.sampled_from(["a", "b", "not", "not_ready", "and", "or", "x1", "always", "c"]),
                      min_size=2, max_size=6, unique=True)


@settings(max_examples=60, deadline=None)
@given(prop_names, st.data())
def test_formula_is_true_exactly_when_at_most_one_is_true(names, data):
    s = MutualExclusion(tuple(names))
    values = dict(zip(names, data.draw(st.lists(st.booleans(), min_size=len(names), max_size=len(names)))))
    expected = sum(values.values()) <= 1
    assert evaluate(s.formula(False), values) == expected
    assert evaluate(s.formula(True), {}, values) == expected
    assert {v.primed for v in variables(s.formula(True))} == {True}
    assert {v.primed for v in variables(s.formula(False))} == {False}


def test_formula_has_the_thesis_shape_for_two():
    # always ((pickup and not drop) or (not pickup and drop) or (not pickup and not drop))  (Fig. 3.8)
    f = MutualExclusion(("pickup", "drop")).formula(False)
    p, d = Var("pickup"), Var("drop")
    assert isinstance(f, Or) and len(f.args) == 3
    assert [t.args for t in f.args] == [(p, Not(d)), (Not(p), d), (Not(p), Not(d))]


def test_sentence():
    assert MutualExclusion(("a", "b")).sentence() == "a and b are mutually exclusive"
    assert MutualExclusion(("topLane", "rightLane", "pickup")).sentence() == \
        "topLane, rightLane and pickup are mutually exclusive"


def test_merging_same_sets_and_dropping_subsets():
    groups = [("/cmd_vel", ["stop", "r1", "r2", "pickup"]), ("/odom", ["pickup", "r1", "r2", "stop"]),
              ("nav/action_topics", ["r1", "r2"]), ("arm/action_topics", ["pickup", "drop"]),
              ("/solo", ["r1"])]
    got = mutual_exclusions(groups, order=["r1", "r2", "stop", "pickup", "drop"])
    assert [(s.propositions, s.topics) for s in got] == [
        (("r1", "r2", "stop", "pickup"), ("/cmd_vel", "/odom", "nav/action_topics")),
        (("pickup", "drop"), ("arm/action_topics",))]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["/t1", "/t2", "/t3", "/t4"]),
                          st.lists(st.sampled_from("abcdef"), min_size=1, max_size=4, unique=True)), max_size=6))
def test_every_conflicting_pair_is_covered_and_no_suggestion_is_redundant(groups):
    got = mutual_exclusions(groups)
    for _, props in groups:
        for p, q in itertools.combinations(props, 2):
            assert any({p, q} <= set(s.propositions) for s in got), (p, q, got)
    sets = [set(s.propositions) for s in got]
    assert not any(a < b for a in sets for b in sets)


def test_add_to_spec_puts_primed_into_trans_and_unprimed_into_init():
    spec = Spec(inputs=["x"], outputs=["a", "b"], sys_safety=[Clause(Var("a", True), "a'", "s.slugsin", 9)])
    s = MutualExclusion(("a", "b"), ("/cmd_vel",))
    new = add_to_spec(spec, [s])
    assert new.sys_safety[0] == spec.sys_safety[0] and len(new.sys_safety) == 2
    assert new.sys_safety[1].formula == s.formula(True)
    assert new.sys_init[-1].formula == s.formula(False)
    assert "a and b are mutually exclusive" in new.sys_safety[1].text and "/cmd_vel" in new.sys_safety[1].text
    assert spec.sys_init == [], "the original spec is not changed"
    env = add_to_spec(spec, [MutualExclusion(("x", "y"), side=ENVIRONMENT)])
    assert len(env.env_safety) == 1 and len(env.env_init) == 1 and env.sys_safety == spec.sys_safety


def test_input_exclusion_names_the_inputs_that_drive_the_outputs():
    lit = Var
    spec = Spec(inputs=["left", "right", "battery"], outputs=["move_left", "move_right", "led"],
                sys_safety=[Clause(Or((Not(lit("left", True)), lit("move_left", True)))),
                            Clause(Or((Not(lit("right", True)), lit("move_right", True)))),
                            Clause(Or((Not(lit("battery", True)), lit("led", True))))])
    got = input_exclusion_for(spec, ["move_left", "move_right"])
    assert got == MutualExclusion(("left", "right"), (), ENVIRONMENT)
    assert input_exclusion_for(spec, ["led"]) is None, "one input alone needs no exclusion"


@pytest.mark.parametrize("n", [2, 3, 9])
def test_size_is_quadratic(n):
    f = MutualExclusion(tuple(f"p{i}" for i in range(n))).formula(True)
    assert len(f.args) == n + 1 and all(len(t.args) == n for t in f.args)


@settings(max_examples=80, deadline=None)
@given(st.sets(st.tuples(st.sampled_from("abcdefg"), st.sampled_from("abcdefg")), max_size=15))
def test_maximal_cliques_cover_every_pair_and_are_cliques_and_maximal(pairs):
    from ltl_stack.analysis.conflicts import maximal_cliques

    edges = {frozenset(p) for p in pairs if p[0] != p[1]}
    cliques = maximal_cliques(pairs)
    for c in cliques:
        assert all(frozenset(e) in edges for e in itertools.combinations(c, 2)), c
        others = {v for e in edges for v in e} - c
        assert not any(all(frozenset((v, u)) in edges for u in c) for v in others), ("not maximal", c)
    for e in edges:
        assert any(e <= c for c in cliques), e
    assert len(set(cliques)) == len(cliques)


@settings(max_examples=30, deadline=None)
@given(prop_names)
def test_slugsin_lines_read_back_to_the_same_constraint(names):
    from ltl_stack.analysis.report import suggestion_forms
    from ltl_stack.spec import parse_slugsin, write_slugsin

    s = MutualExclusion(tuple(names))
    spec = add_to_spec(Spec(inputs=[], outputs=list(names)), [s])
    back = parse_slugsin(write_slugsin(spec), "roundtrip.slugsin")
    forms = suggestion_forms(s)
    assert forms["slugsin"]["SYS_TRANS"] in write_slugsin(spec).split("\n")
    for values in itertools.product([False, True], repeat=len(names)):
        valuation = dict(zip(names, values))
        expected = sum(values) <= 1
        assert evaluate(back.sys_safety[0].formula, {}, valuation) == expected
        assert evaluate(back.sys_init[0].formula, valuation) == expected


def test_english_quotes_names_that_are_sentence_words():
    from ltl_stack.analysis.report import suggestion_forms

    s = MutualExclusion(("not", "and", "not_ready"))
    assert s.sentence() == "'not', 'and' and not_ready are mutually exclusive"
    assert suggestion_forms(s)["english_expanded"].startswith(
        "always (('not' and not 'and' and not not_ready) or (not 'not' and 'and' and not not_ready)")


def test_suggestions_the_spec_already_guarantees_are_marked():
    nand = Not(And((Var("a", True), Var("b", True))))
    both_now = Not(And((Var("a"), Var("b"))))
    s = MutualExclusion(("a", "b"))
    plain = Spec(inputs=["x"], outputs=["a", "b", "c"])
    # nothing keeps a and b apart
    assert [m.in_spec for m in mark_guaranteed(plain, [s])] == [False]
    # only the safety part: the first state may still have both
    safety_only = Spec(inputs=["x"], outputs=["a", "b", "c"], sys_safety=[Clause(nand)])
    assert [m.in_spec for m in mark_guaranteed(safety_only, [s])] == [False]
    full = Spec(inputs=["x"], outputs=["a", "b", "c"], sys_safety=[Clause(nand)], sys_init=[Clause(both_now)])
    marked = mark_guaranteed(full, [s, MutualExclusion(("a", "c"))])
    assert [m.in_spec for m in marked] == [True, False]
    assert marked[0].to_dict()["already_in_spec"] is True and marked[0].propositions == s.propositions

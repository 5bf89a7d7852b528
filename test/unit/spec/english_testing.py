"""Test-side evaluators for comparing a compiled English spec with an independent GR(1) encoding.

Written here, not taken from ``ltl_stack.spec``, so that a bug in the library's own evaluation
cannot hide a bug in the English compiler: a direct recursive evaluator (formulas in these tests
are small) and a BDD translation with ``dd`` for exact equivalence of whole sections.
"""
from __future__ import annotations

import random
from pathlib import Path

from dd import autoref

from ltl_stack.spec.formula import And, Const, Formula, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.model import Spec

REPO = Path(__file__).resolve().parents[3]
DATA = REPO / "test" / "data" / "english"
CONFIG = REPO / "config"
SAFETY_AND_INIT = ("env_init", "sys_init", "env_safety", "sys_safety")


def truth(f: Formula, cur: dict[str, bool], nxt: dict[str, bool]) -> bool:
    """The value of ``f``: unprimed names from ``cur``, primed ones from ``nxt``."""
    if isinstance(f, Var):
        return (nxt if f.primed else cur)[f.name]
    if isinstance(f, Const):
        return f.value
    if isinstance(f, Not):
        return not truth(f.arg, cur, nxt)
    if isinstance(f, And):
        return all(truth(a, cur, nxt) for a in f.args)
    if isinstance(f, Or):
        return any(truth(a, cur, nxt) for a in f.args)
    left, right = truth(f.left, cur, nxt), truth(f.right, cur, nxt)
    if isinstance(f, Implies):
        return (not left) or right
    if isinstance(f, Iff):
        return left == right
    assert isinstance(f, Xor)
    return left != right


class Bdds:
    """Formulas over ``names`` (and their primed copies) as BDDs."""

    def __init__(self, names: list[str]):
        self.bdd = autoref.BDD()
        self.names = list(names)
        self.bdd.declare(*names, *(n + "_next" for n in names))

    def of(self, f: Formula):
        b = self.bdd
        if isinstance(f, Var):
            return b.var(f.name + ("_next" if f.primed else ""))
        if isinstance(f, Const):
            return b.true if f.value else b.false
        if isinstance(f, Not):
            return ~self.of(f.arg)
        if isinstance(f, And):
            out = b.true
            for a in f.args:
                out &= self.of(a)
            return out
        if isinstance(f, Or):
            out = b.false
            for a in f.args:
                out |= self.of(a)
            return out
        left, right = self.of(f.left), self.of(f.right)
        if isinstance(f, Implies):
            return ~left | right
        if isinstance(f, Iff):
            return left.equiv(right)
        return ~left.equiv(right)

    def section(self, spec: Spec, name: str):
        out = self.bdd.true
        for clause in spec.section(name):
            out &= self.of(clause.formula)
        return out


def assert_equivalent(ours: Spec, independent: Spec, seed: int = 0, samples: int = 400) -> None:
    """Same propositions; init and safety sections equivalent (exactly, and on random valuations);
    the goals of each liveness section pairwise equivalent (as multisets)."""
    assert sorted(ours.inputs) == sorted(independent.inputs)
    assert sorted(ours.outputs) == sorted(independent.outputs)
    names = [*ours.inputs, *ours.outputs]
    bdds = Bdds(names)
    for section in SAFETY_AND_INIT:
        a, b = bdds.section(ours, section), bdds.section(independent, section)
        assert a == b, f"{section} differs"
        _random_check(ours, independent, section, names, bdds, seed, samples)
    for section in ("env_liveness", "sys_liveness"):
        left = [bdds.of(c.formula) for c in ours.section(section)]
        right = [bdds.of(c.formula) for c in independent.section(section)]
        assert len(left) == len(right), (section, len(left), len(right))
        for goal in left:
            assert goal in right, f"a goal of {section} has no equivalent"
            right.remove(goal)


def _random_check(ours: Spec, independent: Spec, section: str, names: list[str], bdds: Bdds, seed: int,
                  samples: int) -> None:
    """Evaluate both conjunctions on seeded random valuations; half of them satisfy one side, so
    the comparison is not decided by the many clauses every uniform valuation violates."""
    rng = random.Random(seed)
    satisfying = []
    for spec in (ours, independent):
        node = bdds.section(spec, section)
        for k, model in enumerate(bdds.bdd.pick_iter(node, care_vars=set(bdds.bdd.vars))):
            satisfying.append(model)
            if k >= samples // 4:
                break
    for k in range(samples):
        if satisfying and k % 2 == 0:
            model = rng.choice(satisfying)
            cur = {n: model[n] for n in names}
            nxt = {n: model[n + "_next"] for n in names}
        else:
            cur = {n: rng.random() < 0.5 for n in names}
            nxt = {n: rng.random() < 0.5 for n in names}
        a = all(truth(c.formula, cur, nxt) for c in ours.section(section))
        b = all(truth(c.formula, cur, nxt) for c in independent.section(section))
        assert a == b, (section, cur, nxt)

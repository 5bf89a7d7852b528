"""Helpers for the spec tests: shared spec paths, formula strategies, comparing specs."""
from __future__ import annotations

import random
from pathlib import Path

from hypothesis import strategies as st

from ltl_stack.spec.formula import FALSE, TRUE, And, Formula, Iff, Implies, Not, Or, Var, Xor, variables
from ltl_stack.spec.model import SECTIONS, Spec
from ltl_stack.spec.ops import evaluate_many

SHARED = Path(__file__).resolve().parents[3].parent / "shared"
SPECS = SHARED / "specs"


def shared_specs(pattern: str) -> list[Path]:
    """Shared spec files matching ``pattern`` under ``../shared/specs`` (empty when absent)."""
    return sorted(SPECS.glob(pattern)) if SPECS.is_dir() else []


NAMES = ["a", "b", "c", "not_ready", "x@0.0.5", "x@1"]


def formulas(names: list[str] = NAMES, primes: bool = True, max_leaves: int = 25) -> st.SearchStrategy[Formula]:
    """Random formulas over ``names`` using every node type of the model."""
    leaf = st.one_of(
        st.builds(Var, st.sampled_from(names), st.booleans() if primes else st.just(False)),
        st.sampled_from([TRUE, FALSE]),
    )

    def extend(inner):
        return st.one_of(
            st.builds(Not, inner),
            st.builds(lambda xs: And(tuple(xs)), st.lists(inner, min_size=0, max_size=4)),
            st.builds(lambda xs: Or(tuple(xs)), st.lists(inner, min_size=0, max_size=4)),
            st.builds(Xor, inner, inner),
            st.builds(Implies, inner, inner),
            st.builds(Iff, inner, inner),
        )
    return st.recursive(leaf, extend, max_leaves=max_leaves)


def formulas_of(spec: Spec) -> dict[str, list[Formula]]:
    return {name: [c.formula for c in spec.section(name)] for name in SECTIONS}


def same_content(a: Spec, b: Spec) -> None:
    """Assert two specs have the same propositions, integers and clause formulas (not locations)."""
    assert a.inputs == b.inputs, (a.inputs, b.inputs)
    assert a.outputs == b.outputs, (a.outputs, b.outputs)
    assert a.integers == b.integers, (a.integers, b.integers)
    for name in SECTIONS:
        got = [c.formula for c in b.section(name)]
        expected = [c.formula for c in a.section(name)]
        assert got == expected, (name, len(got), len(expected))


def random_samples(names: list[str], count: int, seed: int) -> tuple[dict[str, int], dict[str, int], int]:
    """``count`` random valuations of current and next copies of ``names``, one bit per sample."""
    rng = random.Random(seed)
    current = {n: rng.getrandbits(count) for n in names}
    nxt = {n: rng.getrandbits(count) for n in names}
    return current, nxt, (1 << count) - 1


def truth_bits(f: Formula, samples: tuple[dict[str, int], dict[str, int], int]) -> int:
    current, nxt, mask = samples
    return evaluate_many(f, current, nxt, mask)


def section_truth(spec: Spec, section: str, samples) -> int:
    """Bitwise truth of the conjunction of a section's clauses on every sample."""
    value = samples[2]
    for clause in spec.section(section):
        value &= truth_bits(clause.formula, samples)
    return value


def names_in(f: Formula) -> set[str]:
    return {v.name for v in variables(f)}

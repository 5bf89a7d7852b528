"""Formula evaluation is linear in the formula's DAG: a clause whose subformulas are shared
(slugsin's ``$`` buffers) is evaluated once per distinct node, never by expanding the sharing. The
executor evaluates env-safety clauses after a violation while it holds the controller lock; a DAG
of depth 16 with three uses of each level expanded to 3^16 calls (24-40 s without a step).

Work is counted (function calls, ``helpers.work``), never timed."""
from __future__ import annotations

import pytest
from helpers import work

from ltl_stack.runtime.executor.explicit import violated_env_safety
from ltl_stack.runtime.resilience.characterize import _variables
from ltl_stack.runtime.resilience.negotiation import violated_clauses
from ltl_stack.runtime.resilience.resilience_table import violates
from ltl_stack.spec import parse_slugsin
from ltl_stack.spec.formula import And, Formula, Iff, Or, Var, Xor, evaluate, variables, walk
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.ops import size

DEPTH = 12  # 3^12 = 531441 paths through 12 * 6 + 1 nodes


def shared(depth: int) -> Formula:
    """Each level uses the one below three times: DAG size linear in ``depth``, expansion 3^depth."""
    f: Formula = Var("a", True)
    for k in range(depth):
        b = Var(f"b{k}", True)
        f = Or((And((f, b)), Xor(f, Var(f"c{k}")), Iff(f, b)))
    return f


def spec_with(f: Formula) -> Spec:
    names = ["a"] + [f"b{k}" for k in range(DEPTH)] + [f"c{k}" for k in range(DEPTH)]
    return Spec(inputs=names, env_safety=[Clause(f)])


CURRENT = {f"c{k}": False for k in range(DEPTH)}
NEXT = {"a": False, **{f"b{k}": k % 2 == 0 for k in range(DEPTH)}}

CALLS = {
    "evaluate": lambda f: evaluate(f, dict(CURRENT), dict(NEXT)),
    "walk": lambda f: list(walk(f)),
    "variables": variables,
    "explicit.violated_env_safety": lambda f: violated_env_safety(spec_with(f), CURRENT, NEXT),
    "negotiation.violated_clauses": lambda f: violated_clauses(spec_with(f), CURRENT, NEXT),
    "resilience_table.violates": lambda f: violates(spec_with(f), dict(CURRENT), dict(NEXT)),
    "characterize._variables": _variables,
}


def test_the_formula_is_a_dag_whose_expansion_is_exponential():
    f = shared(DEPTH)
    assert size(f) <= 6 * DEPTH + 1 and len(list(walk(f))) == size(f), size(f)


@pytest.mark.parametrize("name", list(CALLS))
def test_work_is_linear_in_the_dag_size(name):
    call = CALLS[name]
    small, large = (work(lambda d=d: call(shared(d))) for d in (DEPTH // 2, DEPTH))  # noqa: B023
    # twice the DAG: about twice the work (the expansion would be 3^6 = 729 times more)
    assert large < 3 * small and large < 200 * size(shared(DEPTH)), (small, large)


def test_shared_subformulas_keep_their_value_and_the_violation_is_named():
    f = shared(4)
    expanded = parse_slugsin("[INPUT]\na\nb0\n[ENV_TRANS]\n$ 2 | a' b0' & ? 0 ? 0\n").env_safety[0].formula
    assert isinstance(expanded, And) and expanded.args[0] is expanded.args[1]
    assert evaluate(expanded, {}, {"a": False, "b0": False}) is False
    broken = violated_env_safety(spec_with(f), CURRENT, {"a": False, **{f"b{k}": False for k in range(DEPTH)}})
    assert evaluate(f, dict(CURRENT), {"a": False, **{f"b{k}": False for k in range(DEPTH)}}) is (not broken)

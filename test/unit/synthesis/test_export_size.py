"""The default (cooperative) explicit export is no larger than it needs to be (issue 28): of the
cooperative strategy's automaton and the one of the plain relations of the same solution, the
smaller is exported, provided that it never leaves the environment without an admissible input.
Sizes are compared with slugs' exports recorded in docs/benchmarks/explicit.md (slugs is not run in
the suite: test/benchmarks/bench_explicit.py runs it as a peer)."""
from __future__ import annotations

import pytest
from helpers import require_shared

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.explicit import extract, traps_environment
from ltl_stack.synthesis.strategy import SymbolicStrategy

#: slugs --explicitStrategy --jsonOutput, states (docs/benchmarks/explicit.md)
SLUGS = {"fastslow__fastslow_ICRA": 552, "move_group_and_move_base": 472, "multi_robot_scenario": 648,
         "error_resilience_exampleB": 31, "water_reservoir": 191, "single_robot_scenario": 52}


def spec_path(name: str):
    if name == "move_group_and_move_base":
        return require_shared("specs", name, f"{name}.slugsin")
    return require_shared("specs", "benchmarks", "slugsin", f"{name}.slugsin")


@pytest.mark.parametrize("name", list(SLUGS))
def test_the_default_export_is_no_larger_than_slugs(name):
    result = synthesize(load_spec(spec_path(name)))
    automaton = result.strategy.explicit()
    assert len(automaton.states) <= SLUGS[name], (name, len(automaton.states))
    assert not traps_environment(result.game, automaton)
    assert automaton.metadata["cooperative"] is True
    # never larger than the cooperative strategy's own automaton
    assert len(automaton.states) <= len(extract(result.strategy).states)


def test_a_smaller_automaton_that_traps_the_environment_is_not_taken():
    """slugs' 2-state export of error_resilience_exampleA wins by leaving the environment no
    admissible input; the cooperative default keeps its 22 states, --no-cooperative gives 2."""
    spec = load_spec(spec_path("error_resilience_exampleA"))
    cooperative = synthesize(spec)
    default = cooperative.strategy.explicit()
    assert not traps_environment(cooperative.game, default)
    ordinary = synthesize(spec, cooperative=False)
    plain = ordinary.strategy.explicit()
    assert len(plain.states) == 2 and traps_environment(ordinary.game, plain)
    assert len(default.states) > len(plain.states)


def test_the_executor_and_the_export_step_the_same_automaton():
    """``explicit`` is deterministic: the executor's automaton (~state ids) is the export's."""
    spec = load_spec(spec_path("fastslow__fastslow_ICRA"))
    a = synthesize(spec).strategy.explicit()
    b = synthesize(spec).strategy.explicit()
    assert [(s.inputs, s.outputs, s.goal, s.successors) for s in a.states] == \
        [(s.inputs, s.outputs, s.goal, s.successors) for s in b.states]


def test_plain_relations_keep_the_cooperative_solution():
    result = synthesize(load_spec(spec_path("fastslow__fastslow_ICRA")))
    plain = SymbolicStrategy(result.game, result.solution, cooperative=False)
    assert result.solution.cooperative and plain.winning == result.strategy.winning

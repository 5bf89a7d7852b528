"""The reference solver itself, on specs whose verdict can be checked by hand.

Each case says why its verdict is what it is; together they pin down the semantics the differential
tests rely on (Mealy moves, env safety violated first, transition goals, both init semantics).
"""
from __future__ import annotations

import pytest
import reference_solver
from random_specs import formula_has_prime, make_spec, random_spec

# (name, spec sections, realizable with slugs' default init, realizable with robotics init)
CASES = [
    ("no constraints", dict(), True, True),
    ("sys safety false: the robot cannot move",
     dict(sys_safety=["0"]), False, False),
    ("sys safety false but env safety false too: the env violates first",
     dict(sys_safety=["0"], env_safety=["0"]), True, True),
    ("env can only move from i=0, sys cannot move: env_init forces the env's deadlock at once",
     dict(env_init=["i"], env_safety=["! i"], sys_safety=["0"]), True, True),
    ("Mealy: the output may copy the next input",
     dict(sys_safety=["! ^ o' i'"]), True, True),
    ("the current output cannot predict the next input",
     dict(sys_safety=["! ^ o i'"]), False, False),
    ("predicting the next input is easy when env safety fixes it",
     dict(sys_safety=["! ^ o i'"], env_safety=["! ^ i' ! i"], sys_init=["! ^ o ! i"]), True, True),
    ("... and without sys_init only the default init semantics lets the robot pick o = !i",
     dict(sys_safety=["! ^ o i'"], env_safety=["! ^ i' ! i"]), True, False),
    ("goal o but o' is forbidden: livelock-free deadlock-free yet losing",
     dict(sys_safety=["! o'"], sys_liveness=["o"]), False, False),
    ("goal on an input: unrealizable without assumption",
     dict(sys_liveness=["i'"]), False, False),
    ("goal on an input: realizable when the env promises it",
     dict(sys_liveness=["i'"], env_liveness=["i"]), True, True),
    ("transition goal: toggle o infinitely often",
     dict(sys_liveness=["^ o o'"]), True, True),
    ("transition goal: toggle o, but o stays true once true",
     dict(sys_liveness=["^ o o'"], sys_safety=["| ! o o'"]), False, False),
    ("robotics init: a bad initial output makes it unrealizable, the default picks a good one",
     dict(sys_safety=["! o"]), True, False),
    ("robotics init: sys_init excludes the bad initial output",
     dict(sys_safety=["! o"], sys_init=["! o"]), True, True),
    ("default init: no initial output satisfies sys_init for i",
     dict(env_init=["i"], sys_init=["& o ! o"]), False, True),
    ("env safety depends on the current output; sys safety forbids what the env must do",
     dict(env_safety=["| ! o i'"], sys_safety=["! i'"]), False, False),
    ("the robot keeps o false so the env must keep i'=0; robotics init also starts from o=1 and loses",
     dict(env_safety=["| o ! i'"], sys_safety=["! i'"]), True, False),
    ("two goals that alternate with a one-step memory",
     dict(sys_liveness=["o", "! o"]), True, True),
    ("two goals, the second unreachable after the first",
     dict(sys_liveness=["o", "! o"], sys_safety=["| ! o o'"]), False, False),
    ("waiting: goal o & i, env promises i while o holds",
     dict(sys_liveness=["& o i"], env_liveness=["| i ! o"]), True, True),
    ("Mealy: goal o & i, env promises i or o; the robot answers i' with o'",
     dict(sys_liveness=["& o i"], env_liveness=["| i o"]), True, True),
    ("goal o & i' needs o before i', and the env may play i' = !o while keeping i | o",
     dict(sys_liveness=["& o i'"], env_liveness=["| i o"]), False, False),
]


@pytest.mark.parametrize("name, sections, default, robotics", CASES, ids=[c[0] for c in CASES])
def test_hand_checked_verdicts(name, sections, default, robotics):
    spec = make_spec(["i"], ["o"], **sections)
    got = (reference_solver.is_realizable(spec), reference_solver.is_realizable(spec, robotics_semantics=True))
    assert got == (default, robotics), got


def test_winning_positions_of_a_two_output_game():
    # o1 must follow i' exactly, o2 may never go back from true to false; goal: o2 false.
    spec = make_spec(["i"], ["o1", "o2"], sys_safety=["! ^ o1' i'", "| ! o2 o2'"], sys_liveness=["! o2"])
    game = reference_solver.build_game(spec)
    winning = reference_solver.winning_positions(game)
    # positions indexed [x][y] with y bits (o1, o2): winning exactly when o2 is false
    got = {(x, y) for x in range(2) for y in range(4) if winning[x, y]}
    assert got == {(0, 0), (0, 1), (1, 0), (1, 1)}, got


def test_env_safety_may_not_mention_primed_outputs():
    spec = make_spec(["i"], ["o"], env_safety=["| i' o'"])
    with pytest.raises(ValueError, match="primed output"):
        reference_solver.build_game(spec)


def test_generator_is_seeded_and_every_section_is_nontrivial():
    assert random_spec(7) == random_spec(7)
    assert random_spec(7) != random_spec(8)
    for seed in range(40):
        spec = random_spec(seed)
        assert 2 <= len(spec.inputs) <= 4 and 2 <= len(spec.outputs) <= 4, (spec.inputs, spec.outputs)
        grid = reference_solver.Grid(spec.inputs, spec.outputs)
        for section in ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness"):
            clauses = spec.section(section)
            assert clauses, (seed, section)
            for clause in clauses:
                values = grid.evaluate(clause.formula)
                assert values.any() and not values.all(), (seed, section, clause)
        assert all(formula_has_prime(c.formula) for c in spec.sys_liveness), seed
        assert all(formula_has_prime(c.formula) for c in spec.sys_safety + spec.env_safety), seed

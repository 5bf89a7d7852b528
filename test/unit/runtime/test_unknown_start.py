"""Property: the outputs a robot holds before its start while inputs were never heard of
(``modes.safe_initial_outputs``) keep [SYS_INIT] and every rho_s clause for every value of them —
whatever they do while the outputs are held — with the fewest outputs changed from those wanted;
when no valuation does, the clauses are named. Checked by enumeration on random specs."""
from __future__ import annotations

import itertools

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_safe_every_mode import INPUTS, OUTPUTS, keeps, specs

from ltl_stack.runtime.executor.output_guard import safe_initial_outputs
from ltl_stack.spec import parse_structured
from ltl_stack.synthesis.game import Game

VALUATIONS = [dict(zip(OUTPUTS, bits)) for bits in itertools.product([False, True], repeat=len(OUTPUTS))]


def held_safely(clauses, init, known, unknown, outputs) -> bool:
    """``outputs`` keep [SYS_INIT] (``init``: output -> value) and every clause for any move that
    keeps them, the ``known`` inputs, and changes the ``unknown`` ones in any way."""
    if any(outputs[o] != v for o, v in init.items()):
        return False
    values = [dict(zip(unknown, bits)) for bits in itertools.product([False, True], repeat=len(unknown))]
    return all(keeps(clauses, {**known, **now, **outputs}, {**known, **before, **outputs})
               for before in values for now in values)


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(specs(), st.fixed_dictionaries({o: st.sampled_from([None, False, True]) for o in OUTPUTS}),
       st.lists(st.sampled_from(INPUTS), min_size=1, unique=True), st.booleans(), st.sampled_from(VALUATIONS))
def test_the_outputs_held_before_the_start_are_safe_for_every_value_of_the_unknown_inputs(spec_and_clauses, init,
                                                                                        unknown, value, wanted):
    text, clauses = spec_and_clauses
    init = {o: v for o, v in init.items() if v is not None}
    literals = "".join(f"{'' if v else '!'}{o}\n" for o, v in init.items()) or "TRUE\n"
    text = text.replace("[SYS_INIT]\n!x\n!y\n!z\n", f"[SYS_INIT]\n{literals}")
    game = Game(parse_structured(text, "prop.structuredslugs"))
    known = {p: value for p in INPUTS if p not in unknown}
    guarded = safe_initial_outputs(game, known, wanted, unknown)
    safe = [v for v in VALUATIONS if held_safely(clauses, init, known, unknown, v)]
    if not safe:
        assert guarded.unkeepable and guarded.outputs == wanted
        return
    assert not guarded.unkeepable and guarded.outputs in safe
    changes = sum(guarded.outputs[o] != wanted[o] for o in OUTPUTS)
    assert changes == min(sum(v[o] != wanted[o] for o in OUTPUTS) for v in safe)

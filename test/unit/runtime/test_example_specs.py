"""The specs of thesis Examples 10-12 (config/): realizable as the thesis has them, and their
assumptions are the ones the examples break."""
from __future__ import annotations

from pathlib import Path

import pytest

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.errors import AssumptionViolation

CONFIG = Path(__file__).resolve().parents[3] / "config"
SPECS = ["block_cutting/block_cutting", "block_cutting/block_cutting_two_robots", "alice/alice",
         "patrol_recycling/patrol_recycling"]


@pytest.mark.parametrize("name", SPECS)
def test_example_specs_are_realizable(name):
    assert synthesize(load_spec(CONFIG / f"{name}.structuredslugs")).realizable


def test_spec5_is_spec4_with_lines_2_and_3_replaced():
    """§4.3: 'If the block is placed by another robot, we replace line 2 and 3 in Spec. 4 with Spec. 5.'"""
    four = load_spec(CONFIG / "block_cutting" / "block_cutting.structuredslugs")
    five = load_spec(CONFIG / "block_cutting" / "block_cutting_two_robots.structuredslugs")
    assert [c.text for c in five.sys_init] == [c.text for c in four.sys_init]
    assert [c.text for c in five.sys_safety] == [c.text for c in four.sys_safety]
    assert [c.text for c in four.env_safety] == ["(pickupTask' & !holdingBlock') -> blockPresent'"]
    assert [c.text for c in five.env_safety] == ["!blockPresent' -> placeBlock_Bob'"]
    assert five.inputs == [*four.inputs, "placeBlock_Bob"]


def test_spec4_pickup_without_a_block_breaks_the_assumption_and_never_actuates_pickup():
    """Example 10: a pickup task while nothing is held and no block is there is outside the
    assumptions (the plain strategy has no move: 'unknown robot action'); whenever a move exists,
    pickup is actuated only with a block present."""
    strategy = synthesize(load_spec(CONFIG / "block_cutting" / "block_cutting.structuredslugs")).strategy
    quiet = {"pickupTask": False, "holdingBlock": False, "blockPresent": False}
    state = strategy.initial_state(inputs=quiet)
    with pytest.raises(AssumptionViolation):
        strategy.step(state, {**quiet, "pickupTask": True})
    moved = strategy.step(state, {**quiet, "pickupTask": True, "blockPresent": True})
    assert moved.outputs["pickup"] is True
    assert strategy.step(state, {**quiet, "blockPresent": True}).outputs["pickup"] is False

"""Thesis Example 13 (§4.10.3) in process: D blocked at the door, characterization fails, D negotiates
with A (A adds "open the door when D is in road or storage"), D delivers; C negotiates with A to pass
the ingredients, A passes, C cooks, D returns to company. And the §4.10.4 comparison: base case,
recovery only, characterization only."""
from __future__ import annotations

from kitchen_world import KITCHEN, ROBOTS, KitchenWorld

from ltl_stack.runtime.config.mapping import load_mapping
from ltl_stack.runtime.resilience.characterize import Mode
from ltl_stack.runtime.resilience.negotiation import Outcome, assumptions_about, classes_from_mapping
from ltl_stack.spec import load_spec
from ltl_stack.spec.formula import variables
from ltl_stack.synthesis import synthesize


def test_the_three_specs_are_realizable_and_their_classes_match_them():
    for name in ROBOTS.values():
        spec = load_spec(KITCHEN / f"{name}.structuredslugs")
        assert synthesize(spec).realizable, name
        assert classes_from_mapping(load_mapping(KITCHEN / f"{name}.yaml")).check(spec) == [], name


def test_phi_t_of_a_in_ds_spec_is_spec_7_lines_5_and_6():
    spec = load_spec(KITCHEN / "delivery_agent.structuredslugs")
    classes = classes_from_mapping(load_mapping(KITCHEN / "delivery_agent.yaml"))
    assert [c.text.strip() for c in assumptions_about(spec, classes, "A")] == [
        "prepArea_c_A'", "(road_c' | storage_c') -> openDoor_A'"]
    assert [c.text.strip() for c in assumptions_about(spec, classes, "C")] == ["cookingArea_c_C'"]


def test_d_blocked_at_the_door_is_unrealizable_after_characterization():
    """D in road with the ingredients, the door closed (A does not open it): characterization
    succeeds once (arriving in road, EC2), then leaves D's spec unrealizable with EC1 and EC2 (Alg. 3:
    without a peer to negotiate with, D waits for the user)."""
    world = KitchenWorld("ec")
    world.run(8)
    d = world.strategies["D"]
    assert world.where == "road" and world.outputs("D")["orderReceived"] and not world.outputs("A")["openDoor"]
    assert d.mode is Mode.WAITING_FOR_USER and d.counters.unrealizable == 1
    last = d.characterizer.history[-1]
    assert not last.realizable and last.variant == "EC2"
    core = [c.text.strip() for _, c in d.explanation.core]
    assert "!openDoor_A' -> !storage'" in core and "orderReceived -> (storage & storage_c)" in core


def test_example_13_narrative(tmp_path):
    world = KitchenWorld("negotiation", written=tmp_path)
    world.run(20)
    summary = world.summary()
    first, second = summary["negotiations"]
    # D negotiates with A when blocked in road; both adopt (4.8.1)
    assert first["peer"] == "A" and first["session"] == "D->A" and first["case"] == Outcome.BOTH_ADOPT.name
    assert "always, if next road_c_D or next storage_c_D then next openDoor" in " ".join(first["sent"])
    # A's assumption "D never in the kitchen" is over D's completion sensors: D keeps it by its activations
    # (ownership), never as a guarantee over what it senses
    assert any("not (next cookingArea or next prepArea)" in r for r in first["received"]), first["received"]
    # C negotiates with A to pass the ingredients; both adopt
    assert second["peer"] == "A" and second["session"] == "C->A" and second["case"] == Outcome.BOTH_ADOPT.name
    assert "always, if next ingredientArrived then next passIngredient" in " ".join(second["sent"])
    blocked = world.first(lambda h: h["where"] == "road" and h["D"]["orderReceived"])
    opened = world.first(lambda h: h["A"]["openDoor"])
    assert blocked is not None and opened is not None and opened > blocked
    assert summary["delivered"] is not None and summary["passed"] > summary["delivered"]
    assert summary["cooked"] > summary["passed"]
    assert summary["back_in_company"] > summary["delivered"]
    assert summary["violation_raised"] == [] and set(summary["modes"].values()) == {"normal"}
    # what ~state counts (the controller view shows it): A answered two negotiations and adopted twice,
    # D and C started one each and adopted its outcome
    counters = {r: world.strategies[r].counters for r in ("A", "C", "D")}
    assert {r: (c.negotiations, c.negotiated) for r, c in counters.items()} == {"A": (2, 2), "C": (1, 1), "D": (1, 1)}
    assert all(c.resyntheses >= c.negotiated for c in counters.values())
    # A's adopted spec holds both negotiated guarantees, was written atomically and loads
    a_text = (tmp_path / "kitchen_assistant.negotiated.structuredslugs").read_text()
    assert a_text.count("Alg. 4 line 5: assumption of C") == 2 and "(road_c_D' | storage_c_D') -> openDoor'" in a_text
    assert synthesize(load_spec(tmp_path / "kitchen_assistant.negotiated.structuredslugs")).realizable
    d_spec = load_spec(tmp_path / "delivery_agent.negotiated.structuredslugs")
    sensed = [c.text for c in d_spec.sys_safety
              if any(v.primed and v.name in d_spec.inputs for v in variables(c.formula))
              and not any(v.primed and v.name in d_spec.outputs for v in variables(c.formula))]
    assert sensed == [], sensed  # no guarantee D's next move cannot keep
    assert not (tmp_path / "chef.negotiated.structuredslugs.tmp").exists()
    # a second conflict between the same pair would not negotiate again
    assert world.negotiators["D"].choose(world.specs["D"], {**world.inputs("D"), **world.outputs("D")},
                                         {**world.inputs("D"), "road_c": True, "company_c": False}) is None


def test_comparison_4_10_4():
    """Base case: D's controller has no next state in road (a violation every step); recovery: D
    waits in front of the door forever; characterization alone: unrealizable, waiting for the user;
    negotiation: completes (previous test)."""
    results = {}
    for mode in ("base", "recovery", "ec"):
        world = KitchenWorld(mode)
        world.run(15)
        results[mode] = world.summary()
        assert results[mode]["delivered"] is None and results[mode]["waiting_in_road"], mode
    assert results["base"]["violation_raised"] == ["D"]
    assert results["recovery"]["violation_raised"] == [] and results["recovery"]["modes"]["D"] == Mode.RECOVERING.value
    assert results["ec"]["modes"]["D"] == Mode.WAITING_FOR_USER.value


def test_received_clauses_keep_ownership():
    """A received clause with a next-state output of ours is a guarantee as it is; one over our
    completion sensors goes onto the activations when our assumptions make the rewrite imply it
    (a completion appears only where we were or headed); one over a sensor we do not complete (a
    global sensor) stays as sent: a guarantee, which phi^nego's synthesis then decides."""
    from ltl_stack.runtime.resilience.negotiation.ownership import split_by_ownership
    from ltl_stack.spec import parse_structured

    spec = parse_structured("[INPUT]\nroad_c\nkitchen_c\narrived\n\n[OUTPUT]\nroad\nkitchen\nopenDoor\n\n"
                            "[ENV_TRANS]\nkitchen_c' -> (kitchen_c | kitchen)\n\n"
                            "[SYS_TRANS]\narrived' -> openDoor'\n!(kitchen_c')\nroad_c' -> !arrived'\n", "got")
    position = dict.fromkeys(spec.inputs + spec.outputs, False)
    owned = split_by_ownership(list(spec.sys_safety), spec, position)
    assert [c.text.strip() for c in owned.by_move + owned.rewritten] == ["arrived' -> openDoor'", "!kitchen'"]
    assert [c.text.strip() for c in owned.literal] == ["road_c' -> !arrived'"]
    assert [c.location for c in owned.guarantees] == ["got:15", "got:16", "got:17"]
    # from a position in the kitchen the rewrite does not keep "never in the kitchen": kept as sent
    owned = split_by_ownership(list(spec.sys_safety), spec, {**position, "kitchen_c": True})
    assert [c.text.strip() for c in owned.literal] == ["!(kitchen_c')", "road_c' -> !arrived'"]

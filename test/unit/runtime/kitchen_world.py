"""Thesis Example 13 (§4.10.3) in process, without ROS: the three robots of config/kitchen/ each run
a ``runtime.Controller`` over a ``ResilientStrategy``, in a small world that moves D where it heads
(through the door only when A opens it), completes an action one tick after it was activated, and
keeps the global sensor ``ingredientArrived`` (set by D's delivery, cleared once A has passed the
ingredients). Used by the unit tests and by the §4.10.4 comparison (test/benchmarks/bench_negotiation.py).

Modes (§4.10.4): ``base`` (neither recovery nor characterization), ``recovery``, ``ec`` (environment
characterization only: S.1, the user would be asked), ``negotiation`` (characterization, then Alg. 4).
"""
from __future__ import annotations

from pathlib import Path

from ltl_stack.runtime.config.mapping import load_mapping
from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.resilience.characterize import Mode, ResilientStrategy, Threshold
from ltl_stack.runtime.resilience.negotiation import Negotiator, classes_from_mapping
from ltl_stack.spec import load_spec
from ltl_stack.synthesis.errors import AssumptionViolation

KITCHEN = Path(__file__).resolve().parents[3] / "config" / "kitchen"
ROBOTS = {"D": "delivery_agent", "A": "kitchen_assistant", "C": "chef"}
REGIONS = ["company", "road", "storage", "prepArea", "cookingArea"]
NEIGHBOURS = {"company": {"road"}, "road": {"company", "storage"}, "storage": {"road", "prepArea"},
              "prepArea": {"storage", "cookingArea"}, "cookingArea": {"prepArea"}}


class KitchenWorld:
    """The three robots and their shared world; ``tick()`` advances everything by one step."""

    def __init__(self, mode: str = "negotiation", *, order_at: int = 1, written: Path | None = None) -> None:
        self.mode = mode
        self.t = 0
        self.order_at = order_at
        self.specs = {r: load_spec(KITCHEN / f"{name}.structuredslugs") for r, name in ROBOTS.items()}
        self.negotiators = {}
        self.strategies: dict[str, ResilientStrategy] = {}
        self.controllers: dict[str, Controller] = {}
        self.raised: dict[str, AssumptionViolation | None] = dict.fromkeys(ROBOTS)
        for robot, name in ROBOTS.items():
            classes = classes_from_mapping(load_mapping(KITCHEN / f"{name}.yaml"))
            negotiator = Negotiator(classes, transport=self._transport)
            self.negotiators[robot] = negotiator
            rs = ResilientStrategy(
                self.specs[robot], recovery=mode == "recovery", characterize=mode in ("ec", "negotiation"),
                threshold=Threshold(), negotiate=negotiator.hook if mode == "negotiation" else None,
                path=(written / f"{name}.negotiated.structuredslugs") if written else None)
            self.strategies[robot] = rs
            self.controllers[robot] = Controller(rs, settle_steps=0)  # one transition per tick
        self.where = "company"
        self.order = False
        self.arrived = False
        self.completed = {"pickup": False, "deliver": False, "passIngredient": False, "cooking": False}
        self.history: list[dict] = []
        self._start()

    def _transport(self, peer):
        return lambda message: self.negotiators[peer.name].serve(message, self.strategies[peer.name],
                                                                 self.controllers[peer.name])

    # --- what each robot senses ------------------------------------------------------------------
    def outputs(self, robot: str) -> dict[str, bool]:
        return self.controllers[robot].current_outputs()

    def _d_location(self, suffix: str) -> dict[str, bool]:
        return {f"{r}{suffix}": self.where == r for r in REGIONS}

    def inputs(self, robot: str) -> dict[str, bool]:
        a = self.outputs("A") if self.controllers["A"].started else {"openDoor": False, "passIngredient": False}
        if robot == "D":
            return {**self._d_location("_c"), "pickup_c": self.completed["pickup"],
                    "deliver_c": self.completed["deliver"], "order": self.order, "openDoor_A": a["openDoor"],
                    "prepArea_c_A": True, "cookingArea_c_C": True}
        if robot == "A":
            d = self._d_location("_c_D")
            return {"prepArea_c": True, "passIngredient_c": self.completed["passIngredient"],
                    "ingredientArrived": self.arrived, "cookingArea_c_C": True, **d}
        d = self._d_location("_c_D")
        return {"cookingArea_c": True, "cooking_c": self.completed["cooking"], "ingredientArrived": self.arrived,
                "prepArea_c_A": True, "passIngredient_A": a["passIngredient"],
                "passIngredient_c_A": self.completed["passIngredient"], "company_c_D": d["company_c_D"],
                "prepArea_c_D": d["prepArea_c_D"], "cookingArea_c_D": d["cookingArea_c_D"]}

    # --- stepping -----------------------------------------------------------------------------------
    def _start(self) -> None:
        for robot in ("A", "C", "D"):
            self.controllers[robot].report_many(self.inputs(robot))

    def _drive(self, robot: str) -> None:
        controller = self.controllers[robot]
        update = controller.report_many(self.inputs(robot))
        if not update.stepped and update.violation is None:
            update = controller.tick()
        self.raised[robot] = update.violation

    def tick(self) -> dict:
        """One step: the world moves (D, completions, sensors), then A, C and D step in that order
        (A reacts to where D is at this step, as D's assumption asks)."""
        self.t += 1
        d, a, c = self.outputs("D"), self.outputs("A"), self.outputs("C")
        heading = [r for r in REGIONS if d[r]]
        if heading and heading[0] in NEIGHBOURS[self.where]:
            if not (heading[0] == "storage" and self.where == "road" and not a["openDoor"]):
                self.where = heading[0]
        self.completed = {"pickup": d["pickup"], "deliver": d["deliver"], "passIngredient": a["passIngredient"],
                          "cooking": c["cooking"]}
        if self.completed["deliver"]:
            self.arrived = True
        if self.completed["passIngredient"]:
            self.arrived = False
        self.order = (self.t >= self.order_at and not d["orderReceived"] and not self._delivered_once())
        for robot in ("A", "C", "D"):
            self._drive(robot)
        record = {"t": self.t, "where": self.where, "arrived": self.arrived, "order": self.order,
                  "D": self.outputs("D"), "A": self.outputs("A"), "C": self.outputs("C"),
                  "completed": dict(self.completed), "modes": {r: s.mode for r, s in self.strategies.items()},
                  "raised": {r: v for r, v in self.raised.items() if v is not None}}
        self.history.append(record)
        return record

    def _delivered_once(self) -> bool:
        return any(h["completed"]["deliver"] for h in self.history) or self.completed["deliver"]

    def run(self, ticks: int) -> list[dict]:
        for _ in range(ticks):
            self.tick()
        return self.history

    # --- the narrative -----------------------------------------------------------------------------
    def first(self, predicate) -> int | None:
        """The first tick whose record satisfies ``predicate``."""
        return next((h["t"] for h in self.history if predicate(h)), None)

    def summary(self) -> dict:
        """What §4.10.4 compares: did D deliver, did C cook, did D return; what each robot ended as."""
        delivered = self.first(lambda h: h["completed"]["deliver"])
        cooked = self.first(lambda h: h["completed"]["cooking"])
        back = self.first(lambda h: delivered is not None and h["t"] > delivered and h["where"] == "company")
        return {"mode": self.mode, "delivered": delivered, "passed": self.first(lambda h: h["completed"]["passIngredient"]),
                "cooked": cooked, "back_in_company": back,
                "modes": {r: s.mode.value for r, s in self.strategies.items()},
                "violation_raised": sorted({r for h in self.history for r in h["raised"]}),
                "waiting_in_road": self.where == "road" and self.strategies["D"].mode is not Mode.ABORTED,
                "negotiations": [n for r in ("D", "A", "C") for n in self.negotiators[r].reports()
                                 if n["initiator"]]}

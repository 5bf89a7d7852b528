"""``kitchen_world``: the simulated workspace of thesis Example 13 (§4.10.3, Fig. 4.2) on proposition
topics, headless. Three robots under one scenario namespace (``/kitchen`` in ``launch/kitchen.launch``):

* DeliveryAgent ``D`` moves between company, road, storage, prepArea and cookingArea: heading for a
  neighbouring region (its output ``<ns>/D/outputs/<region>``) it arrives there after ``~move_time``
  seconds — except into storage from road while KitchenAssistant ``A`` does not open the door
  (``<ns>/A/outputs/openDoor``): then it stays in road. Its location is ``<ns>/D/inputs/<region>_c``;
* durative actions (D's pickup and deliver, A's passIngredient, C's cooking) complete
  ``~action_time`` seconds after they were activated (``<ns>/<R>/inputs/<action>_c``) and the
  completion falls with the activation, as ``action_proposition`` does;
* A stays in prepArea and Chef ``C`` in cookingArea (``<ns>/A/inputs/prepArea_c``,
  ``<ns>/C/inputs/cookingArea_c``, always true);
* D's order (``<ns>/D/inputs/order``) comes ``~order_after`` seconds after D's controller runs and
  stays until D has picked the ingredients up (one order); the global sensor ``<ns>/ingredientArrived``
  (Sen_G) rises when D's delivery completes and falls when A's passing completes.

The other robots' propositions reach each executor through its mapping (config/kitchen/*.yaml: an eAP
input is the other robot's output or input topic). The node narrates what happens on ``~events``
(``std_msgs/String``) and its log.
"""
from __future__ import annotations

import time
from typing import Any

import rospy
from std_msgs.msg import Bool, String

from ltl_stack.ros.proposition_node import NodeSpec, Param, PropositionGroup, run_node
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.sim.environment import starts_clock

REGIONS = ("company", "road", "storage", "prepArea", "cookingArea")
NEIGHBOURS = {"company": {"road"}, "road": {"company", "storage"}, "storage": {"road", "prepArea"},
              "prepArea": {"storage", "cookingArea"}, "cookingArea": {"prepArea"}}
ACTIONS = {"D": ("pickup", "deliver"), "A": ("passIngredient",), "C": ("cooking",)}

KITCHEN_WORLD = NodeSpec(
    name="kitchen_world",
    kind="sim",
    description="The simulated workspace of thesis Example 13 (three robots, a door, a global sensor).",
    params=[
        Param("move_time", 1.0, "seconds D takes to reach a neighbouring region", bound=Bound.POSITIVE),
        Param("action_time", 0.5, "seconds an activated action takes to complete", bound=Bound.POSITIVE),
        Param("order_after", 2.0, "seconds after D's controller runs until the order comes",
              bound=Bound.NON_NEGATIVE),
        Param("rate", 20.0, "how often (Hz) the world advances", bound=Bound.RATE),
        Param("start_on", "D/controller_executor/state", "start the clock at the first message on this topic "
              "(relative to the node's namespace; a controller's ~state once the controller has started)",
              kind=str),
    ],
)


class KitchenWorld:
    def __init__(self, config: dict[str, Any]) -> None:
        self.config = config
        # every sensor of the world in one group: the sensors one tick changes (D leaves a region and
        # enters the next) are one ~valuation message, which each robot's executor reads as one update
        self.sensors = PropositionGroup(rate=0.0)
        self.values: dict[str, bool] = {}
        self.outputs: dict[str, bool] = {}
        self.where = "company"
        self.moving: tuple[str, float] | None = None     # (target, since)
        self.activated: dict[str, float | None] = {}
        self.order_given = False
        self.started: float | None = None
        self.events = rospy.Publisher("~events", String, queue_size=100, latch=True)
        for robot, actions in ACTIONS.items():
            for action in actions:
                self.activated[f"{robot}/{action}"] = None
        watched = [f"D/outputs/{r}" for r in REGIONS] + ["D/outputs/orderReceived"] + ["A/outputs/openDoor"] + [
            f"{robot}/outputs/{a}" for robot, actions in ACTIONS.items() for a in actions]
        self.subs = [rospy.Subscriber(t, Bool, self._on_output, callback_args=t, queue_size=10) for t in watched]
        rospy.Subscriber(config["start_on"], rospy.AnyMsg, self._on_start, queue_size=1)

    # --- topics ------------------------------------------------------------------------------------------
    def _on_output(self, msg: Bool, topic: str) -> None:
        self.outputs[topic] = bool(msg.data)

    def _on_start(self, msg: Any) -> None:
        if self.started is None and starts_clock(msg):  # D's controller has started, wherever it runs
            self.started = time.monotonic()

    def set(self, topic: str, value: bool) -> None:
        """Stage a sensor's value; ``publish_all`` publishes the tick's changes together."""
        self.values[topic] = value

    def say(self, text: str) -> None:
        rospy.loginfo("%s: %s", rospy.get_name(), text)
        self.events.publish(String(text))

    def out(self, topic: str) -> bool:
        return self.outputs.get(topic, False)

    # --- the world ----------------------------------------------------------------------------------------
    def publish_all(self) -> None:
        for r in REGIONS:
            self.set(f"D/inputs/{r}_c", self.where == r)
        self.set("A/inputs/prepArea_c", True)
        self.set("C/inputs/cookingArea_c", True)
        self.set("D/inputs/order", self.order_given and not self._picked_up)
        self.set("ingredientArrived", self.arrived)
        self.sensors.set_many(self.values)

    def advance(self, now: float) -> None:
        heading = [r for r in REGIONS if self.out(f"D/outputs/{r}")]
        target = heading[0] if len(heading) == 1 else None
        if target is None or target == self.where or target not in NEIGHBOURS[self.where]:
            self.moving = None
        elif self.moving is None or self.moving[0] != target:
            self.moving = (target, now)
        elif now - self.moving[1] >= self.config["move_time"]:
            if target == "storage" and self.where == "road" and not self.out("A/outputs/openDoor"):
                pass  # the door is closed: D stays in road
            else:
                self.where, self.moving = target, None
                self.say(f"D is in {target}")
        door_closed = self.where == "road" and not self.out("A/outputs/openDoor")
        if door_closed and self.out("D/outputs/orderReceived") and not self._blocked:
            self.say("D waits in road with the ingredients: the door to storage is closed (A does not open it)")
            self._blocked = True
        elif not door_closed and self._blocked:
            self.say("A opens the door")
            self._blocked = False
        for robot, actions in ACTIONS.items():
            for action in actions:
                key = f"{robot}/{action}"
                active = self.out(f"{robot}/outputs/{action}")
                if not active:
                    self.activated[key] = None
                elif self.activated[key] is None:
                    self.activated[key] = now
                done = active and now - self.activated[key] >= self.config["action_time"]
                if done and not self.values.get(f"{robot}/inputs/{action}_c"):
                    self.on_completed(robot, action)
                self.set(f"{robot}/inputs/{action}_c", done)
        if not self.order_given and self.started is not None and now - self.started >= self.config["order_after"]:
            self.order_given = True
            self.say("D receives an order for ingredients")
        if self.out("D/outputs/orderReceived"):
            self._picked_up = True
        self.publish_all()

    def on_completed(self, robot: str, action: str) -> None:
        if (robot, action) == ("D", "deliver"):
            self.arrived = True
            self.say("D delivered the ingredients to storage: ingredientArrived")
        elif (robot, action) == ("A", "passIngredient"):
            self.arrived = False
            self.say("A passed the ingredients to C")
        elif (robot, action) == ("C", "cooking"):
            self.say("C cooked the ingredients")
        elif (robot, action) == ("D", "pickup"):
            self.say("D picked up the ingredients at company")

    _picked_up = False
    _blocked = False
    arrived = False

    def spin(self) -> None:
        self.publish_all()
        rate = rospy.Rate(self.config["rate"])
        while not rospy.is_shutdown():
            self.advance(time.monotonic())
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                return


def kitchen_world_main() -> None:
    run_node(KITCHEN_WORLD, KitchenWorld)

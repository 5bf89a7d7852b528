"""``story_environment``: play a story (``ltl_stack.runtime.resilience.story``) against a running controller.

The environment of a thesis example that reacts to the robot: each of the executor's ``~state``
messages is one transition (the executor steps at a fixed ``--rate``), except while it characterizes
or waits for the user: the story's clock then stands still, as when the story is played in process
(``resilience_table``), where those steps take no transition, so a beat due "after N transitions"
never overtakes a characterization however long its synthesis takes; where the robot is comes
from its region inputs (``r_c``) in that message, what it does from the outputs. When the next
beat is due, the node publishes the inputs it sets (``std_msgs/Bool``, latched, on the
controller's input topics ``inputs/<name>``); a pulse goes back to false once a ``~state`` shows
the controller has stepped with it (not while it is characterizing or waiting for the user). When the executor's mode is ``waiting_for_user`` (thesis Alg. 3: the
characterized spec is unrealizable) and the story names the user's env liveness, the node calls
the executor's real ``~add_env_liveness`` service with it, as a user would with the
``add_env_liveness`` tool. What happens is published on ``~fired`` (std_msgs/String: ``story: …``,
``user: …``) and ``~complete`` (std_msgs/Bool, latched) turns true when every beat has fired.
"""
from __future__ import annotations

import threading
import time
from typing import Any

import rospy
from std_msgs.msg import Bool, String

from ltl_stack.msg import ControllerState
from ltl_stack.ros.proposition_node import NodeConfigError, NodeSpec, Param, PropositionGroup, run_node
from ltl_stack.ros.valuation import MalformedValuation, state_valuations
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.runtime.executor.node_mode import Mode
from ltl_stack.runtime.resilience.story import StoryError, StoryPlayer, load_story, region_of
from ltl_stack.spec import SpecError, load_spec
from ltl_stack.srv import AddEnvLiveness

STORY_ENVIRONMENT = NodeSpec(
    name="story_environment",
    kind="sim",
    description="Play a story (config/<example>/story.yaml) against a running controller executor: "
                "inputs that react to the robot, and the user's env liveness through ~add_env_liveness.",
    params=[
        Param("story", "", "story YAML file (format: ltl_stack/runtime/resilience/story.py)", kind=str, required=True),
        Param("spec", "", "the controller's spec: check the story's names against it (optional)", kind=str),
        Param("executor", "controller_executor", "the controller executor node (its ~state, "
              "~add_env_liveness)", kind=str, ros_name=True),
        Param("inputs_ns", "inputs", "namespace of the controller's input topics", kind=str, ros_name=True),
        Param("wait_for_subscribers", 5.0, "wait up to this long (s) for a listener on ~fired before "
              "playing (so a demo sees the first beat)", bound=Bound.NON_NEGATIVE),
        Param("service_timeout", 60.0, "wait up to this long (s) for ~add_env_liveness", bound=Bound.POSITIVE),
    ],
)


#: modes in which the controller observed the inputs but has not moved on them yet
BUSY = (Mode.CHARACTERIZING.value, Mode.WAITING_FOR_USER.value)


class StoryEnvironment:
    def __init__(self, config: dict[str, Any]) -> None:
        name = rospy.get_name()
        try:
            self.story = load_story(config["story"])
            if config["spec"]:
                self.story.check(load_spec(config["spec"]))
        except (StoryError, SpecError) as error:
            raise NodeConfigError(f"{name}: {error}") from None
        self.config = config
        self.player = StoryPlayer(self.story)
        ns = config["inputs_ns"].rstrip("/")
        # the story's inputs in one group: a beat that changes several is one ~valuation message, which the
        # executor reads as one update
        self.inputs = PropositionGroup(rate=0.0)
        self.topics = {n: f"{ns}/{n}" for n in self.story.inputs}
        self.fired_pub = rospy.Publisher("~fired", String, queue_size=100, latch=True)
        self.complete_pub = rospy.Publisher("~complete", Bool, queue_size=1, latch=True)
        self.executor = config["executor"].rstrip("/")
        self.lock = threading.Lock()
        self.asked = False
        self.announced = False

    def spin(self) -> None:
        self.complete_pub.publish(Bool(False))
        self._publish_values()
        deadline = time.monotonic() + self.config["wait_for_subscribers"]
        while not rospy.is_shutdown() and time.monotonic() < deadline and self.fired_pub.get_num_connections() == 0:
            rospy.sleep(0.05)
        rospy.loginfo("%s: playing %d beats from %s", rospy.get_name(), len(self.story.beats), self.story.source)
        rospy.Subscriber(f"{self.executor}/state", ControllerState, self._on_state, queue_size=100)
        rospy.spin()

    def _say(self, text: str) -> None:
        rospy.loginfo("%s: %s", rospy.get_name(), text)
        self.fired_pub.publish(String(data=text))

    def _publish_values(self) -> None:
        self.inputs.set_many({self.topics[name]: value for name, value in self.player.values.items()})

    def _on_state(self, msg: ControllerState) -> None:
        try:
            inputs, outputs = state_valuations(msg)
        except MalformedValuation as err:
            rospy.logwarn_throttle(60, "%s: skipping a controller state that cannot be read: %s", rospy.get_name(), err)
            return
        mode = getattr(msg, "mode", "")
        with self.lock:
            if mode not in BUSY:  # the story's clock stands still while the executor characterizes or asks
                self._step(inputs, outputs)
            if mode == Mode.WAITING_FOR_USER.value and self.story.user and not self.asked:
                self.asked = True
                threading.Thread(target=self._user, daemon=True).start()

    def _step(self, inputs: dict[str, bool], outputs: dict[str, bool]) -> None:
        """One controller transition: read pulses the controller stepped with, fire the next beat if due."""
        pulses = self.player.pending_pulses()
        if pulses and all(inputs.get(p) for p in pulses):
            self.player.read()  # the controller has stepped with them (not just observed them for EC)
        self.player.not_seen_yet(inputs)
        beat = self.player.tick(region_of(inputs, self.story.regions, "_c"), outputs)
        if beat is not None:
            self._say(f"story: {beat.name}")
        self._publish_values()
        if self.player.complete and not self.announced:
            self.announced = True
            self._say("story: complete")
            self.complete_pub.publish(Bool(True))

    def _user(self) -> None:
        """Alg. 3 line 6 as the user does it: the executor's ~add_env_liveness service."""
        text = self.story.user
        service = f"{self.executor}/add_env_liveness"
        self._say(f"user: adds the env liveness GF({text}) through {rospy.resolve_name(service)}")
        try:
            rospy.wait_for_service(service, self.config["service_timeout"])
            answer = rospy.ServiceProxy(service, AddEnvLiveness)(text)
        except (rospy.ROSException, rospy.ServiceException) as error:
            self._say(f"user: the call failed: {error}")
        else:
            self._say(f"user: the executor answered: {'realizable' if answer.success else 'not done'}: "
                      f"{answer.message} (mode {answer.mode})")
        with self.lock:
            self.asked = False if not self.player.complete else self.asked


def story_environment_main() -> None:
    run_node(STORY_ENVIRONMENT, StoryEnvironment)

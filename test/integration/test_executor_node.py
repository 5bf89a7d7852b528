"""The controller executor node against a real master, with the real synthesizer.

A *probe* (a small rospy process started by the test, fed JSON commands on stdin) plays the input
proposition nodes, listens to the output topics, ``~state`` (with the resilience fields) and
``/diagnostics``, and calls the executor's services; everything it receives comes back as JSON lines.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import pytest
from helpers import run_script, wait_for

pytestmark = pytest.mark.ros

# out follows a, busy follows lock; the environment promises that lock, once set, stays set.
LOCK_SPEC = (Path(__file__).resolve().parents[1] / "unit" / "runtime" / "lock.slugsin").read_text()
LOCK_CLAUSE_LINE = 10

PROBE = textwrap.dedent('''\
    import json, sys, threading, time
    import rospy
    from std_msgs.msg import Bool
    from std_srvs.srv import SetBool, Trigger
    from diagnostic_msgs.msg import DiagnosticArray
    from ltl_stack.msg import ControllerState
    from ltl_stack.srv import AddEnvLiveness

    rospy.init_node("probe", anonymous=True, disable_signals=True)
    out_lock = threading.Lock()

    def emit(**kw):
        kw["t"] = time.monotonic()
        with out_lock:
            sys.stdout.write(json.dumps(kw) + "\\n")
            sys.stdout.flush()

    def valuation(v):
        return dict(zip(v.keys, [bool(x) for x in v.values]))

    def on_bool(msg, topic):
        emit(kind="bool", topic=topic, value=msg.data)

    def on_state(msg, topic):
        emit(kind="state", topic=topic, state=msg.state_id, goal=msg.goal_index, running=msg.running,
             inputs=valuation(msg.inputs), outputs=valuation(msg.outputs), mode=msg.mode,
             violations=msg.violations, recovery_steps=msg.recovery_steps, unsafe_steps=msg.unsafe_steps,
             resyntheses=msg.resyntheses, ec1=msg.resyntheses_ec1, ec2=msg.resyntheses_ec2,
             user=msg.resyntheses_user, unrealizable=msg.unrealizable, violated=list(msg.violated_clauses),
             spec_file=msg.spec_file, generation=msg.strategy_generation)

    def on_diag(msg, topic):
        for s in msg.status:
            emit(kind="diag", level=s.level, name=s.name, message=s.message,
                 values=[[kv.key, kv.value] for kv in s.values])

    handlers = {"bool": (Bool, on_bool), "state": (ControllerState, on_state), "diag": (DiagnosticArray, on_diag)}
    subs = []
    for arg in sys.argv[1:]:
        kind, topic = arg.split(":", 1)
        cls, cb = handlers[kind]
        subs.append(rospy.Subscriber(topic, cls, cb, callback_args=topic, queue_size=1000))
    pubs = {}
    emit(kind="up")
    for line in sys.stdin:
        cmd = json.loads(line)
        if cmd["op"] == "pub":
            pub = pubs.get(cmd["topic"])
            if pub is None:
                pub = pubs[cmd["topic"]] = rospy.Publisher(cmd["topic"], Bool, queue_size=10, latch=True)
            deadline = time.monotonic() + 30
            while pub.get_num_connections() < 1 and time.monotonic() < deadline:
                time.sleep(0.01)
            pub.publish(Bool(cmd["value"]))
            emit(kind="published", topic=cmd["topic"], value=cmd["value"])
        elif cmd["op"] == "call":
            rospy.wait_for_service(cmd["service"], 30)
            resp = rospy.ServiceProxy(cmd["service"], SetBool)(cmd["value"])
            emit(kind="called", success=resp.success, message=resp.message)
        elif cmd["op"] == "liveness":
            rospy.wait_for_service(cmd["service"], 30)
            r = rospy.ServiceProxy(cmd["service"], AddEnvLiveness)(cmd["formula"])
            emit(kind="called", success=r.success, message=r.message, mode=r.mode, code=r.code)
        elif cmd["op"] == "abort":
            rospy.wait_for_service(cmd["service"], 30)
            r = rospy.ServiceProxy(cmd["service"], Trigger)()
            emit(kind="called", success=r.success, message=r.message)
    ''')


class Probe:
    """A rospy process that publishes inputs on request and reports what it receives."""

    def __init__(self, master, workdir: Path, listen: list[str], name: str = "probe"):
        script = workdir / "probe.py"
        script.write_text(PROBE)
        env = dict(master.env)
        self.popen = subprocess.Popen([sys.executable, str(script), *listen], env=env, stdin=subprocess.PIPE,
                                      stdout=subprocess.PIPE, stderr=open(workdir / f"{name}.err", "wb"),  # noqa: SIM115
                                      text=True, start_new_session=True)
        self.events: list[dict] = []
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        wait_for(lambda: self.of("up"), 90, "the probe to start")

    def _read(self) -> None:
        for line in self.popen.stdout:
            if line.startswith("{"):
                self.events.append(json.loads(line))

    def of(self, kind: str, **match) -> list[dict]:
        return [e for e in list(self.events) if e["kind"] == kind and all(e.get(k) == v for k, v in match.items())]

    def send(self, **command) -> None:
        self.popen.stdin.write(json.dumps(command) + "\n")
        self.popen.stdin.flush()

    def publish(self, topic: str, value: bool) -> None:
        count = len(self.of("published", topic=topic))
        self.send(op="pub", topic=topic, value=value)
        wait_for(lambda: len(self.of("published", topic=topic)) > count, 90, f"publishing {topic}={value}")

    def call(self, service: str, value: bool) -> dict:
        count = len(self.of("called"))
        self.send(op="call", service=service, value=value)
        return wait_for(lambda: self.of("called")[count:], 90, f"calling {service}")[0]

    def last(self, topic: str) -> bool | None:
        values = self.of("bool", topic=topic)
        return values[-1]["value"] if values else None

    def wait_value(self, topic: str, value: bool, timeout: float = 30) -> None:
        wait_for(lambda: self.last(topic) is value, timeout, f"{topic} == {value} (seen {self.of('bool', topic=topic)})")

    def stop(self) -> None:
        if self.popen.poll() is None:
            os.killpg(self.popen.pid, signal.SIGKILL)
            self.popen.wait(10)


@pytest.fixture
def probes(ros_master, tmp_path):
    started: list[Probe] = []

    def start(listen: list[str], name: str = "probe") -> Probe:
        probe = Probe(ros_master, tmp_path, listen, name=f"{name}{len(started)}")
        started.append(probe)
        return probe

    yield start
    for probe in started:
        probe.stop()


@pytest.fixture
def lock_spec(tmp_path) -> Path:
    path = tmp_path / "lock.slugsin"
    path.write_text(LOCK_SPEC)
    return path


STATE = "/controller_executor/state"
A, LOCK = "/lock/inputs/a", "/lock/inputs/lock"
OUT, BUSY = "/lock/outputs/out", "/lock/outputs/busy"
LISTEN = [f"bool:{OUT}", f"bool:{BUSY}", f"state:{STATE}", "diag:/diagnostics"]


def start_executor(ros_master, spec: Path, *extra: str):
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), *extra], name="executor")
    ros_master.wait_for_subscriber(A)
    ros_master.wait_for_subscriber(LOCK)
    return node


def test_ready_handshake_names_silent_inputs_then_steps_on_changes(ros_master, probes, lock_spec):
    executor = start_executor(ros_master, lock_spec, "--ready-timeout", "1")
    probe = probes(LISTEN)
    probe.wait_value(OUT, False)  # every output starts false (latched)
    probe.publish(A, True)
    log = executor.wait_output("from input(s) lock (/lock/inputs/lock)", timeout=90)
    assert "no message after" in log, log
    assert [s["state"] for s in probe.of("state")] == [-1] * len(probe.of("state")), probe.of("state")
    assert probe.last(OUT) is False, probe.of("bool")

    probe.publish(LOCK, False)
    probe.wait_value(OUT, True)
    first = wait_for(lambda: [s for s in probe.of("state") if s["state"] >= 0], 90, "the initial state")[0]
    assert first["inputs"] == {"a": True, "lock": False} and first["outputs"] == {"out": True, "busy": False}, first
    executor.wait_output("initial state")

    # Repeated readings do not step; a change steps at once.
    steps = len([s for s in probe.of("state") if s["state"] >= 0])
    for _ in range(3):
        probe.publish(A, True)
    probe.publish(A, False)
    probe.wait_value(OUT, False)
    wait_for(lambda: len([s for s in probe.of("state") if s["state"] >= 0]) == steps + 1, 90, "one more state")
    probe.publish(LOCK, True)
    probe.wait_value(BUSY, True)
    # ~state and the outputs are different topics: ROS does not promise which message arrives first
    wait_for(lambda: len([s for s in probe.of("state") if s["state"] >= 0]) == steps + 2, 90, "the state after lock")
    states = [s for s in probe.of("state") if s["state"] >= 0]
    assert [s["inputs"] for s in states] == [{"a": True, "lock": False}, {"a": False, "lock": False},
                                             {"a": False, "lock": True}], states
    assert all(s["running"] for s in states), states


def test_pause_by_service_and_topic_drives_every_output_false(ros_master, probes, lock_spec):
    start_executor(ros_master, lock_spec)
    probe = probes(LISTEN)
    probe.publish(A, True)
    probe.publish(LOCK, True)
    probe.wait_value(OUT, True)
    probe.wait_value(BUSY, True)

    reply = probe.call("/controller_executor/set_running", False)
    assert reply == {**reply, "success": True, "message": "paused"}, reply
    probe.wait_value(OUT, False)
    probe.wait_value(BUSY, False)
    wait_for(lambda: probe.of("state") and probe.of("state")[-1]["running"] is False, 90, "running false in ~state")
    # While paused, input changes do not move the outputs.
    probe.publish(A, False)
    probe.publish(A, True)
    assert probe.last(OUT) is False, probe.of("bool", topic=OUT)

    probe.publish("/controller_executor/running", True)
    probe.wait_value(OUT, True)
    probe.wait_value(BUSY, True)
    probe.publish("/controller_executor/running", False)
    probe.wait_value(OUT, False)
    assert probe.call("/controller_executor/set_running", True)["message"] == "running"
    probe.wait_value(OUT, True)


@pytest.mark.parametrize("policy", ["hold", "all-false"])
def test_assumption_violation_is_diagnosed_and_outputs_follow_the_policy(ros_master, probes, lock_spec, policy):
    executor = start_executor(ros_master, lock_spec, "--on-violation", policy, "--no-recovery")
    probe = probes(LISTEN)
    probe.publish(A, True)
    probe.publish(LOCK, True)
    probe.wait_value(BUSY, True)

    probe.publish(LOCK, False)  # breaks lock -> lock'
    diag = wait_for(lambda: [d for d in probe.of("diag") if d["level"] == 2], 90, "an ERROR diagnostic")[0]
    assert f"{lock_spec}:{LOCK_CLAUSE_LINE}: | ! lock lock' (always, if lock then next lock)" in diag["message"], diag
    assert ["meaning", "always, if lock then next lock"] in diag["values"], diag
    assert ["clause", f"{lock_spec}:{LOCK_CLAUSE_LINE}: | ! lock lock'"] in diag["values"], diag
    log = executor.wait_output("environment assumption violated")
    assert "Traceback" not in log, log
    # Lemma 1(a): both policies keep busy' <-> lock' and out' <-> a' (a valuation keeps them):
    # hold changes the one output that breaks them, all-false leaves true only what they need
    probe.wait_value(BUSY, False)
    probe.wait_value(OUT, True)
    assert probe.last(BUSY) is False and probe.last(OUT) is True, probe.of("bool")
    # The node is alive and answers; once the inputs are admissible again it continues.
    probe.publish(A, False)
    probe.publish(LOCK, True)
    probe.wait_value(BUSY, True)
    probe.wait_value(OUT, False)
    executor.wait_output("inputs admissible again")
    assert executor.running(), executor.output()


def test_init_props_with_true_and_false_values_start_without_waiting(ros_master, probes, lock_spec):
    executor = start_executor(ros_master, lock_spec, "--init-props", "a=1,lock=0", "--json")
    probe = probes(LISTEN)
    probe.wait_value(OUT, True)
    probe.wait_value(BUSY, False)
    first = wait_for(lambda: [s for s in probe.of("state") if s["state"] >= 0], 90, "the initial state")[0]
    assert first["inputs"] == {"a": True, "lock": False}, first
    # A live reading replaces the assumed one.
    probe.publish(A, False)
    probe.wait_value(OUT, False)
    probe.publish(A, True)
    probe.wait_value(OUT, True)
    def json_events():
        return [json.loads(x) for x in executor.output().splitlines() if x.startswith("{")]

    wait_for(lambda: len(json_events()) >= 3, 90, "three JSON events from --json")
    events = json_events()
    assert [(e["event"], e["inputs"], e["outputs"]) for e in events] == [
        ("start", {"a": True, "lock": False}, {"out": True, "busy": False}),
        ("step", {"a": False, "lock": False}, {"out": False, "busy": False}),
        ("step", {"a": True, "lock": False}, {"out": True, "busy": False})], events
    # Shutting down leaves every output false.
    executor.stop()
    probe.wait_value(OUT, False)


def test_the_node_publishes_the_options_it_runs_with(ros_master, lock_spec):
    start_executor(ros_master, lock_spec, "--rate", "5", "--no-cooperative", "_settle_steps:=3",
                   "_on_violation:=all-false")

    def effective():
        code, _msg, value = ros_master.proxy().getParam("/pytest", "/controller_executor/effective_options")
        return value if code == 1 else None

    options = wait_for(effective, 90, "~effective_options on the parameter server")
    assert {k: options[k] for k in ("rate", "cooperative", "settle_steps", "on_violation", "robotics_semantics",
                                    "characterize", "heartbeat")} == {
        "rate": 5.0, "cooperative": False, "settle_steps": 3, "on_violation": "all-false",
        "robotics_semantics": True, "characterize": False, "heartbeat": 0.25}, options


def test_second_publisher_on_an_input_topic_is_warned_about(ros_master, probes, lock_spec):
    executor = start_executor(ros_master, lock_spec, "--publisher-check-period", "0.3")
    first, second = probes([], "one"), probes([], "two")
    first.publish(A, True)
    second.publish(A, True)
    log = executor.wait_output("has 2 publishers", timeout=90)
    line = next(x for x in log.splitlines() if "has 2 publishers" in x)
    assert "input 'a': topic /lock/inputs/a" in line and line.count("/probe_") == 2, line


def test_mapping_topics_and_namespace_are_used(ros_master, probes, lock_spec, tmp_path):
    mapping = tmp_path / "lock.yaml"
    mapping.write_text(textwrap.dedent("""\
        inputs:
          a:
            node: '/scen/inputs/a'
            node_publish_topic: '/scen/inputs/a'
          lock:
            node: '/scen/inputs/lock'
            node_publish_topic: '/scen/inputs/lock_sensor'
        outputs:
          out:
            - node: '/scen/outputs/r1/out'
              node_subscribe_topic: '/scen/outputs/out'
            - node: '/scen/outputs/r2/out'
              node_subscribe_topic: '/scen/outputs/out'
        """))
    ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(lock_spec), str(mapping)], name="executor")
    ros_master.wait_for_subscriber("/scen/inputs/lock_sensor")
    probe = probes(["bool:/scen/outputs/out", "bool:/scen/outputs/busy"])
    probe.publish("/scen/inputs/a", True)
    probe.publish("/scen/inputs/lock_sensor", True)
    probe.wait_value("/scen/outputs/out", True)
    probe.wait_value("/scen/outputs/busy", True)


@pytest.mark.parametrize("extra, fragment", [
    (["--init-props", "a=1,nope=0"], "unknown proposition 'nope'"),
    (["--on-violation", "explode"], "invalid choice: 'explode'"),
])
def test_bad_arguments_end_in_one_error_without_traceback(ros_master, lock_spec, extra, fragment):
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(lock_spec), *extra], name="executor")
    assert node.popen.wait(30) == 2, node.output()
    assert fragment in node.output() and "Traceback" not in node.output(), node.output()


def test_bad_spec_and_mapping_exit_2_naming_file_and_line(tmp_path, lock_spec):
    bad_spec = tmp_path / "bad.slugsin"
    bad_spec.write_text("[INPUT]\na\n\n[SYS_TRANS]\n& a\n")
    bad_map = tmp_path / "bad.yaml"
    bad_map.write_text("inputs:\n  a:\n    node: x\n  ghost:\n    node: y\n")
    for args, fragment in (([str(bad_spec)], f"{bad_spec}:5"),
                           ([str(lock_spec), str(bad_map)], f"{bad_map}:4: input 'ghost' is not a proposition")):
        proc = run_script(["rosrun", "ltl_stack", "controller_executor", *args, "--check"], capture_output=True,
                              text=True, timeout=300)
        assert proc.returncode == 2, proc
        assert fragment in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
        assert proc.stderr.count("error:") == 1 and proc.stderr.endswith("\n") and \
            proc.stderr.splitlines()[-1].startswith("controller_executor: error: "), proc.stderr


def test_rate_steps_without_input_changes_and_start_paused_waits(ros_master, probes, tmp_path):
    spec = tmp_path / "blink.slugsin"  # out must be true and false infinitely often, whatever a does
    spec.write_text("[INPUT]\na\n\n[OUTPUT]\nout\n\n[SYS_LIVENESS]\nout\n! out\n")
    ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), "--rate", "20", "--start-paused"],
                   name="executor")
    ros_master.wait_for_subscriber("/blink/inputs/a")
    probe = probes(["bool:/blink/outputs/out", f"state:{STATE}"])
    probe.publish("/blink/inputs/a", True)
    wait_for(lambda: probe.of("state") and probe.of("state")[-1]["running"] is False, 90, "a paused ~state")
    assert [s["state"] for s in probe.of("state")] == [-1] * len(probe.of("state")), probe.of("state")
    probe.call("/controller_executor/set_running", True)
    # With the input constant, the 20 Hz steps alone make out blink.
    def changes() -> list:  # the heartbeat republishes the value: count its changes
        values = [e["value"] for e in probe.of("bool", topic="/blink/outputs/out")]
        return [v for k, v in enumerate(values) if k == 0 or values[k - 1] != v]

    wait_for(lambda: len(changes()) >= 5, 90, "out to change 4 times")
    assert len(probe.of("published")) == 1


def test_thesis_simple_example_runs_with_its_own_mapping(ros_master, probes):
    from helpers import require_shared

    spec = require_shared("specs", "simple", "simple.slugsin")
    mapping = require_shared("specs", "simple", "simple.yaml")
    ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping)], name="executor")
    ros_master.wait_for_subscriber("/simple/inputs/sense_object")
    probe = probes([f"state:{STATE}"])
    # The initial state only has to meet the (empty) sys_init; the safety clauses bind every step after it.
    probe.publish("/simple/inputs/person", False)
    probe.publish("/simple/inputs/sense_object", False)
    wait_for(lambda: [s for s in probe.of("state") if s["state"] >= 0], 90, "the initial state")
    for person, sense_object in ((True, False), (True, True), (False, True), (False, False)):
        seen = len(probe.of("state"))
        probe.publish("/simple/inputs/person", person)
        probe.publish("/simple/inputs/sense_object", sense_object)
        want = {"person": person, "sense_object": sense_object}
        state = wait_for(lambda w=want, n=seen: [s for s in probe.of("state")[n:] if s["inputs"] == w],
                         30, f"a state with inputs {want}")[-1]
        outputs = state["outputs"]
        # Example 7 (simple.slugsin): person -> stop_camera, !sense_object -> move, sense_object -> stop.
        assert (not person or outputs["stop_camera"]) and (sense_object or outputs["move"]) and \
            (not sense_object or outputs["stop"]), state


def test_transient_violation_between_two_messages_is_not_reported(ros_master, probes, tmp_path):
    spec = tmp_path / "regions.slugsin"  # the robot is in exactly one of two regions; at1 says it is in r1
    spec.write_text("[INPUT]\nr1\nr2\n\n[OUTPUT]\nat1\n\n[ENV_INIT]\n| & r1 ! r2 & ! r1 r2\n\n"
                    "[ENV_TRANS]\n| & r1' ! r2' & ! r1' r2'\n\n[SYS_TRANS]\n| & at1' r1' & ! at1' ! r1'\n\n"
                    "[SYS_INIT]\n| & at1 r1 & ! at1 ! r1\n")
    executor = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), "--violation-grace", "5.0",
                               "--no-recovery"],
                              name="executor")
    ros_master.wait_for_subscriber("/regions/inputs/r2")
    probe = probes(["bool:/regions/outputs/at1", "diag:/diagnostics"])
    probe.publish("/regions/inputs/r1", True)
    probe.publish("/regions/inputs/r2", False)
    probe.wait_value("/regions/outputs/at1", True)
    # Moving r1 -> r2 arrives as two messages; in between both regions read true. The grace (5 s) is
    # far longer than the gap between the two messages even on a busy machine.
    probe.publish("/regions/inputs/r2", True)
    probe.publish("/regions/inputs/r1", False)
    probe.wait_value("/regions/outputs/at1", False)
    # Now a lasting violation (no region at all): reported after the grace time, once.
    probe.publish("/regions/inputs/r2", False)
    wait_for(lambda: [d for d in probe.of("diag") if d["level"] == 2], 90, "the violation diagnostic")
    log = executor.output()
    reported = [x for x in log.splitlines() if "environment assumption violated" in x]
    assert len(reported) == 1 and "inputs !r1 !r2" in reported[0], log

"""A robot and its controller on two emulated hosts (network namespaces, ``netns_hosts``): what a
partition and a lost master do to the guarantee the stack exists for.

* The cmd_vel story: the executor on host 0, the robot on host 1 — a ``topic_threshold_sensor``
  (person = distance < 2) and two ``set_velocity`` nodes on one cmd_vel (move 0.3 m/s, stop 0 m/s),
  spec ``move' <-> !person'``, ``stop' <-> person'``. Host 1 is cut off and a person appears: the
  robot's ``move`` node stops it on its deadman, the executor marks ``person`` unknown (every output
  false, an ERROR); after the partition both follow the controller again.
* A master cut: the executor and its sensor and actuator on host 1, the master on host 0. With host 1
  cut off from the master, an input change still reaches the outputs (nothing of ours waits for the
  master on the way: the log line of the step used to ask it).
* The spheros one per host (Example 9): a sphero's host cut off, its own output nodes stop it.
* A master cut during a node's start-up parameter read: back within the bound, the node starts;
  away, one error line and a non-zero exit.
"""
from __future__ import annotations

import subprocess
import sys

import pytest
from helpers import SAY, wait_for
from netns_hosts import Hosts, netns_refusal, reachable, start_master
from two_regions import MAPPING as REGION_MAPPING
from two_regions import SPEC as REGION_SPEC

PORT = 11400
SPEC = """[INPUT]
person

[OUTPUT]
move
stop

[ENV_INIT]
!person

[SYS_INIT]
move
!stop

[SYS_TRANS]
move' <-> !person'
stop' <-> person'
"""
MAPPING = """namespace: r
inputs:
  person:
    node: /r/inputs/person
    node_publish_topic: /r/inputs/person
    type: topic_threshold_sensor
outputs:
  move:
    node: /r/outputs/move
    node_subscribe_topic: /r/outputs/move
    type: set_velocity
  stop:
    node: /r/outputs/stop
    node_subscribe_topic: /r/outputs/stop
    type: set_velocity
"""
#: The robot's world: publishes the distance read from a file at 10 Hz, prints every cmd_vel (and how
#: many cmd_vel publishers it hears, when that changes).
WORLD = SAY + '''
import ltl_stack.ros  # noqa: F401 - our rospy fixes, as every node of ours
import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float32

rospy.init_node("world", disable_signals=True)
cmd_vel = rospy.Subscriber("/r/cmd_vel", Twist, lambda m: say("cmd", m.linear.x), queue_size=100)
pub = rospy.Publisher("/r/distance", Float32, queue_size=10)
rate = rospy.Rate(10)
connected = 0
while not rospy.is_shutdown():
    if cmd_vel.get_num_connections() != connected:  # the cmd_vel publishers it hears
        connected = cmd_vel.get_num_connections()
        say("connected", connected)
    try:
        pub.publish(Float32(float(open(sys.argv[1]).read())))
    except ValueError:
        pass
    rate.sleep()
'''


@pytest.fixture
def hosts_factory(tmp_path):
    """``make(count)`` -> Hosts, all removed after the test (also when it fails); skips with the reason
    where network namespaces cannot be made."""
    refusal = netns_refusal()
    if refusal is not None:
        pytest.skip(refusal)
    made: list[Hosts] = []

    def make(count: int) -> Hosts:
        hosts = Hosts(tmp_path, count)
        made.append(hosts)
        return hosts

    try:
        yield make
    finally:
        for hosts in made:
            hosts.close()


def robot(hosts, host: int, env: dict, control) -> None:
    """The robot's nodes on ``host``: the world, the person sensor, the move and stop actuators."""
    script = control.parent / "world.py"
    script.write_text(WORLD)
    hosts.run(host, [sys.executable, str(script), str(control)], env, "world")
    hosts.run(host, ["rosrun", "ltl_stack", "topic_threshold_sensor", "__name:=person_sensor", "_topic:=/r/distance",
                     "_type:=std_msgs/Float32", "_comparison:=<", "_threshold:=2.0",
                     "_proposition_topic:=/r/inputs/person"], env, "sensor")
    for name, vx in (("move", "0.3"), ("stop", "0.0")):
        hosts.run(host, ["rosrun", "ltl_stack", "set_velocity", f"__name:={name}", f"_proposition_topic:=/r/outputs/{name}",
                         "_topic:=/r/cmd_vel", f"_vx:={vx}"], env, name)


def commands(world) -> list[float]:
    return [float(line.split()[1]) for line in world.output().splitlines() if line.startswith("cmd ")]


def files(tmp_path):
    spec, mapping, control = tmp_path / "r.structuredslugs", tmp_path / "r.yaml", tmp_path / "distance"
    spec.write_text(SPEC)
    mapping.write_text(MAPPING)
    control.write_text("5.0")
    return spec, mapping, control


def test_a_partition_stops_the_robot_on_its_deadman_and_the_executor_calls_the_input_unknown(hosts_factory, tmp_path):
    hosts = hosts_factory(2)
    start_master(hosts, 0, PORT)
    spec, mapping, control = files(tmp_path)
    executor = hosts.run(0, ["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping)],
                         hosts.env(0, 0, PORT), "executor")
    robot(hosts, 1, hosts.env(1, 0, PORT), control)
    world = next(p for p in hosts.processes if "world" in p.log_path.name)
    move = next(p for p in hosts.processes if p.log_path.name.endswith("-move.log"))
    wait_for(lambda: 0.3 in commands(world), 90, "the robot moving (cmd_vel 0.3)")

    hosts.cut(1)
    control.write_text("1.0")  # a person in front of the robot, which the executor cannot hear of
    move.wait_output("safe state until it returns", timeout=60)
    executor.wait_output("input(s) unknown: person", timeout=60)
    wait_for(lambda: commands(world)[-1] == 0.0, 60, "cmd_vel 0 after the deadman")
    assert move.output().count("safe state until it returns") == 1  # said once
    assert "no output valuation keeps the system safety for every value of them" in executor.output()
    stopped = len(commands(world))
    wait_for(lambda: "mode inputs_unknown" in executor.output(), 60, "mode inputs_unknown")
    assert 0.3 not in commands(world)[stopped:]  # still stopped: nothing moves it while cut off

    hosts.heal(1)
    executor.wait_output("every input is fresh again", timeout=90)
    control.write_text("5.0")  # the person has gone: the controller moves the robot again
    wait_for(lambda: 0.3 in commands(world)[stopped:], 90, "the robot moving again after the partition")
    assert "heard again: following the controller" in move.output()


def test_with_the_master_cut_off_an_input_change_still_reaches_the_outputs(hosts_factory, tmp_path):
    hosts = hosts_factory(2)
    start_master(hosts, 0, PORT)
    spec, mapping, control = files(tmp_path)
    env = hosts.env(1, 0, PORT)
    executor = hosts.run(1, ["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping)], env, "executor")
    robot(hosts, 1, env, control)
    world = next(p for p in hosts.processes if "world" in p.log_path.name)
    wait_for(lambda: 0.3 in commands(world), 90, "the robot moving (cmd_vel 0.3)")
    executor.wait_output("initial state", timeout=60)
    # the stop node connects to the world through the master: before the cut (on a busy machine it may
    # register after the move node has already moved the robot)
    wait_for(lambda: "connected 2" in world.output(), 90, "the world hearing the move and stop nodes")

    hosts.cut(1)
    wait_for(lambda: not reachable(hosts, 1, hosts.address(0), PORT), 60, "host 1 cut off from the master")
    before, moving = executor.output().count("step to state"), len(commands(world))
    control.write_text("1.0")  # the sensor, executor and actuators are all on host 1: nothing needs the master
    wait_for(lambda: executor.output().count("step to state") > before, 60, "the executor's step")
    # the move node's falling edge sends one zero (the stop node's zeros follow if it has connected to the
    # executor: its subscription may still have been on its way to the master when the cut came)
    wait_for(lambda: 0.0 in commands(world)[moving:], 60, "cmd_vel 0 after the step")
    stopped = moving + commands(world)[moving:].index(0.0) + 1
    control.write_text("5.0")
    wait_for(lambda: 0.3 in commands(world)[stopped:], 60, "the robot moving again, the master still cut off")


#: A robot crossing between regions a and b every second, localized as region_localization does:
#: the whole valuation on ~valuation, then old region off, then new region on, on two Bool topics.
CROSSINGS = '''
import os, sys, time
import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import Bool
from ltl_stack.msg import PropositionValuation
from ltl_stack.ros.valuation import valuation_to_msg

rospy.init_node("localization", disable_signals=True)
topics = {r: rospy.resolve_name("/loc/inputs/" + r + "_rc") for r in "ab"}
bools = {r: rospy.Publisher(t, Bool, queue_size=10, latch=True) for r, t in topics.items()}
whole = rospy.Publisher("~valuation", PropositionValuation, queue_size=10, latch=True)
here = "a"
whole.publish(valuation_to_msg({topics["a"]: True, topics["b"]: False}))
bools["a"].publish(Bool(True))
bools["b"].publish(Bool(False))
while bools["a"].get_num_connections() < 1 or bools["b"].get_num_connections() < 1:
    time.sleep(0.1)
go = sys.argv[2]  # the test creates it once the executor has the first ~valuation
while not os.path.exists(go):
    time.sleep(0.1)
for k in range(int(sys.argv[1])):
    there = "b" if here == "a" else "a"
    whole.publish(valuation_to_msg({topics[here]: False, topics[there]: True}))
    bools[here].publish(Bool(False))
    bools[there].publish(Bool(True))
    here = there
    print("crossing", k + 1, flush=True)
    time.sleep(1.0)
print("done", here, flush=True)
time.sleep(3600)
'''


def test_over_a_slow_lossy_link_a_region_change_is_no_assumption_violation(hosts_factory, tmp_path):
    import shutil

    if shutil.which("ethtool") is None:
        pytest.skip("the lossy link needs ethtool (apt-get install ethtool) to turn checksum offloads off")
    hosts = hosts_factory(2)
    start_master(hosts, 0, PORT)
    hosts.make_lossy(1, 0.2, 0.05, 0.2)  # 200 ± 50 ms, 20 % of the frames lost
    spec, mapping, script = tmp_path / "loc.structuredslugs", tmp_path / "loc.yaml", tmp_path / "crossings.py"
    spec.write_text(REGION_SPEC)
    mapping.write_text(REGION_MAPPING)
    script.write_text(CROSSINGS)
    executor = hosts.run(0, ["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping), "--no-recovery"],
                         hosts.env(0, 0, PORT), "executor")
    crossings = 12
    go = tmp_path / "go"
    robot = hosts.run(1, [sys.executable, str(script), str(crossings), str(go), "__ns:=/loc"], hosts.env(1, 0, PORT),
                      "localization")
    # until the first ~valuation has crossed the lossy link the executor can only read the two Bool
    # topics (a region change is then two messages): the crossings start once it reads the valuation
    wait_for(lambda: "now come from /loc/localization/valuation" in executor.output(), 120,
             "the executor reading the localization's ~valuation")
    go.touch()
    robot.wait_output("done", timeout=180)
    wait_for(lambda: executor.output().count("step to state") >= crossings or "violated" in executor.output(), 120,
             "the executor's steps for every crossing")
    assert "violated" not in executor.output() and "mode holding" not in executor.output(), executor.output()[-3000:]
    assert executor.output().count("step to state") == crossings, executor.output()[-3000:]  # one per crossing
    last = "!a_rc b_rc -> outputs !x" if crossings % 2 else "a_rc !b_rc -> outputs x"
    steps = [line for line in executor.output().splitlines() if "step to state" in line]
    assert steps[-1].endswith(last), executor.output()[-3000:]  # (other lines, e.g. a WARN, may follow)


PEER_SPEC = """[INPUT]
peer_in_hall

[OUTPUT]
enter
wait

[SYS_INIT]
!enter

[SYS_TRANS]
peer_in_hall' -> !enter'
wait' <-> !enter'

[ENV_LIVENESS]
!peer_in_hall

[SYS_LIVENESS]
enter
"""
PEER_MAPPING = """namespace: r
inputs:
  peer_in_hall:
    node: /peer/inputs/in_hall
    node_publish_topic: /peer/inputs/in_hall
    type: topic_threshold_sensor
outputs:
  enter:
    node: /r/outputs/enter
    node_subscribe_topic: /r/outputs/enter
    type: set_velocity
  wait:
    node: /r/outputs/wait
    node_subscribe_topic: /r/outputs/wait
    type: set_velocity
"""
#: The peer's world: its distance to the hall, read from a file, at 10 Hz.
PEER_WORLD = SAY + '''
import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import Float32

rospy.init_node("peer_world", disable_signals=True)
pub = rospy.Publisher("/peer/distance", Float32, queue_size=10)
rate = rospy.Rate(10)
while not rospy.is_shutdown():
    pub.publish(Float32(float(open(sys.argv[1]).read())))
    rate.sleep()
'''


def test_a_robot_starts_while_its_peers_host_is_down_and_runs_normally_once_the_peer_reports(hosts_factory, tmp_path):
    """The robot (host 1) reads whether its peer is in the hall from the peer's sensor (host 2), whose
    host is down when the robot starts: after --ready-timeout the peer's proposition is unknown, the
    robot's outputs are those safe for every value of it (wait, not enter) and the executor says so;
    once the peer's host is up and its sensor reports, the strategy starts and the robot enters."""
    hosts = hosts_factory(3)
    start_master(hosts, 0, PORT)
    spec, mapping, distance = tmp_path / "r.structuredslugs", tmp_path / "r.yaml", tmp_path / "peer_distance"
    spec.write_text(PEER_SPEC)
    mapping.write_text(PEER_MAPPING)
    distance.write_text("5.0")
    env = hosts.env(1, 0, PORT)
    script = tmp_path / "world.py"
    script.write_text(WORLD)
    (tmp_path / "own_distance").write_text("5.0")  # (the world also publishes a distance nobody reads here)
    world = hosts.run(1, [sys.executable, str(script), str(tmp_path / "own_distance")], env, "world")
    for name, vx in (("enter", "0.3"), ("wait", "0.0")):
        hosts.run(1, ["rosrun", "ltl_stack", "set_velocity", f"__name:={name}", f"_proposition_topic:=/r/outputs/{name}",
                      "_topic:=/r/cmd_vel", f"_vx:={vx}"], env, name)
    executor = hosts.run(1, ["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping),
                             "--ready-timeout", "3"], env, "executor")

    executor.wait_output("input(s) unknown: peer_in_hall (/peer/inputs/in_hall, no message yet)", timeout=120)
    wait_for(lambda: "mode inputs_unknown" in executor.output(), 60, "mode inputs_unknown")
    assert "publishing outputs !enter wait" in executor.output(), executor.output()[-3000:]
    wait_for(lambda: 0.0 in commands(world), 90, "the wait node's zero cmd_vel (the safe outputs)")
    assert 0.3 not in commands(world)  # never entered while the peer might be in the hall
    assert "no message after" not in executor.output()  # the start no longer waits for it: no ERROR

    peer_env = hosts.env(2, 0, PORT)  # the peer's host comes up
    peer = tmp_path / "peer_world.py"
    peer.write_text(PEER_WORLD)
    hosts.run(2, [sys.executable, str(peer), str(distance)], peer_env, "peer-world")
    hosts.run(2, ["rosrun", "ltl_stack", "topic_threshold_sensor", "__name:=in_hall", "_topic:=/peer/distance",
                  "_type:=std_msgs/Float32", "_comparison:=<", "_threshold:=2.0",
                  "_proposition_topic:=/peer/inputs/in_hall"], peer_env, "peer-sensor")
    executor.wait_output("every input has reported; started in state", timeout=120)
    wait_for(lambda: 0.3 in commands(world), 90, "the robot entering once the peer reported")
    entered = commands(world).index(0.3)
    distance.write_text("1.0")  # the peer enters the hall: the robot waits (a normal step)
    wait_for(lambda: 0.0 in commands(world)[entered:], 90, "the robot waiting for the peer")


def test_example_8_split_over_two_hosts_tells_the_thesis_story(hosts_factory, tmp_path):
    """Clean and patrol (Example 8) with the controller on host 2 and the robot — the simulated youBot,
    move_base and arm servers, the camera and every proposition node — on host 1, started by the demo
    with the documented per-host commands: the demo tells the whole Fig. 3.10 story from the remote
    controller's ~state."""
    import json

    from ltl_stack.sim.narration import KEYS

    hosts = hosts_factory(3)
    start_master(hosts, 0, PORT)
    controller = hosts.run(2, ["roslaunch", "ltl_stack", "clean_and_patrol_propositions.launch", "start_inputs:=false",
                               "start_outputs:=false", "executor_args:=--input-window 0.05"], hosts.env(2, 0, PORT),
                           "controller")
    controller.wait_output("waiting for every input to report", timeout=180)
    uri = hosts.env(1, 0, PORT)["ROS_MASTER_URI"]
    demo = hosts.run(1, [sys.executable, "-m", "ltl_stack.sim.demo", "--master-uri", uri, "--launch-arg",
                         "start_executor:=false", "--json", "--timeout", "900"], hosts.env(1, 0, PORT), "demo")
    demo.wait_output('"event": "summary"', timeout=960)
    summary = json.loads(next(line for line in demo.output().splitlines() if '"event": "summary"' in line))
    assert summary["ok"] and summary["story"] == list(KEYS), demo.output()[-4000:]
    told = [json.loads(line) for line in demo.output().splitlines() if line.startswith("{") and '"story"' in line
            and '"chapter"' in line]
    regions = {e["chapter"]: e["region"] for e in told}
    assert regions["pickup"] == "bottomLane" and regions["drop"] == "rightGround", told


#: What sphero_wpw's host hears: every cmd_vel (vx vy), every deadman status, and a tick of its own
#: every 0.5 s (the test waits for ticks, never for a duration).
SPHERO_WATCH = SAY + '''
import ltl_stack.ros  # noqa: F401
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Twist

rospy.init_node("watch", disable_signals=True)
rospy.Subscriber("/spheros/sphero_wpw/cmd_vel", Twist, lambda m: say("cmd", m.linear.x, m.linear.y), queue_size=100)
rospy.Subscriber("/diagnostics", DiagnosticArray, lambda m: [say("diag", s.level, s.name)
                 for s in m.status if s.name.endswith(": deadman")], queue_size=100)
while not rospy.is_shutdown():
    say("tick")
    rospy.sleep(0.5)
'''
#: The tag detector shows the left arrow for ever: the spheros move left (move_left, vy 0.3).
LEFT_FOR_EVER = """events:
  - {at: 0.0, topic: tags/right_arrow, value: false}
  - {at: 0.0, topic: tags/up_arrow, value: false}
  - {at: 0.0, topic: tags/down_arrow, value: false}
  - {at: 0.0, topic: tags/stop_sign, value: false}
  - {at: 0.0, topic: tags/left_arrow, value: true}
"""


def sphero_lines(watch) -> list[str]:
    return [line for line in watch.output().splitlines() if line.startswith(("cmd ", "tick", "diag "))]


def moving(line: str) -> bool:
    return line.startswith("cmd ") and any(float(v) != 0.0 for v in line.split()[1:])


def stopped_for_ticks(lines: list[str], ticks: int) -> bool:
    """The last moving command is followed by a zero one and then ``ticks`` ticks (no move since)."""
    last_move = max((i for i, line in enumerate(lines) if moving(line)), default=-1)
    rest = lines[last_move + 1:]
    zero = next((i for i, line in enumerate(rest) if line.startswith("cmd ")), None)
    return zero is not None and sum(line == "tick" for line in rest[zero:]) >= ticks


def test_spheros_one_per_host_a_cut_spheros_own_output_nodes_stop_it_on_their_deadman(hosts_factory, tmp_path):
    """Example 9 split as docs/several_machines.md says: the controller, the tag inputs and the tag
    detector on host 0, sphero_wpw's simulated robot and its output nodes on host 1. Host 1 is cut off:
    its own move_left node's deadman sends the zero Twist and says so; after the partition it follows
    the controller again. (With the output nodes on the controller's host, as before, the robot's last
    command went on standing: nothing on the robot's host stopped it.)"""
    hosts = hosts_factory(2)
    start_master(hosts, 0, PORT)
    schedule, watch_script = tmp_path / "left.yaml", tmp_path / "watch.py"
    schedule.write_text(LEFT_FOR_EVER)
    watch_script.write_text(SPHERO_WATCH)
    robot_env = hosts.env(1, 0, PORT)
    watch = hosts.run(1, [sys.executable, str(watch_script)], robot_env, "watch")
    wait_for(lambda: "tick" in watch.output(), 120, "the watcher on sphero_wpw's host")
    hosts.run(1, ["roslaunch", "ltl_stack", "spheros.launch", "robots:=sphero_wpw", "start_executor:=false",
                  "start_shared:=false", "start_world:=false"], robot_env, "sphero_wpw")
    hosts.run(0, ["roslaunch", "ltl_stack", "spheros.launch", "robots:=none", f"environment:={schedule}"],
              hosts.env(0, 0, PORT), "controller")
    wait_for(lambda: any(moving(line) for line in sphero_lines(watch)), 180, "sphero_wpw moving left")

    hosts.cut(1)
    wait_for(lambda: stopped_for_ticks(sphero_lines(watch), 4), 90, "sphero_wpw stopped by its own output nodes")
    lines = sphero_lines(watch)
    assert any(line.startswith("diag 1 ") and "sphero_wpw_move_left: deadman" in line for line in lines), lines[-40:]

    hosts.heal(1)
    seen = len(sphero_lines(watch))
    wait_for(lambda: any(moving(line) for line in sphero_lines(watch)[seen:]), 120,
             "sphero_wpw following the controller again after the partition")


#: topic_threshold_sensor, held between its registration and its start-up parameter read until the
#: file argv[1] exists (so that the test cuts the master off exactly there).
HELD_SENSOR = '''
import os, sys, time
import ltl_stack.ros  # noqa: F401
from ltl_stack.ros import proposition_node
from ltl_stack.ros.sensors import threshold_sensor_main

registered = proposition_node.init_node

def init_then_wait(*args, **kwargs):
    registered(*args, **kwargs)
    print("registered", flush=True)
    while not os.path.exists(go):
        time.sleep(0.05)
    print("reading its parameters", flush=True)

go = sys.argv.pop(1)
proposition_node.init_node = init_then_wait
threshold_sensor_main()
'''


def held_sensor(hosts, tmp_path, name: str):
    script, go = tmp_path / "held_sensor.py", tmp_path / f"go-{name}"
    script.write_text(HELD_SENSOR)
    node = hosts.run(1, [sys.executable, str(script), str(go), f"__name:={name}", "_topic:=/r/distance",
                         "_type:=std_msgs/Float32", "_comparison:=<", "_threshold:=2.0",
                         f"_proposition_topic:=/r/inputs/{name}"], hosts.env(1, 0, PORT), name)
    node.wait_output("registered", timeout=120)
    return node, go


def test_a_master_cut_during_the_start_up_parameter_read(hosts_factory, tmp_path):
    """A node reads its parameters from the master at start-up (``ros.master.read_param``, bounded):
    cut off from the master right then, it starts normally when the master is back within the
    bound, and otherwise stops with one line naming the master, a non-zero exit, no traceback."""
    import shutil

    if shutil.which("ss") is None:
        pytest.skip("the test sees the node's read waiting for the master with ss (iproute2)")
    hosts = hosts_factory(2)
    start_master(hosts, 0, PORT)
    back, go_back = held_sensor(hosts, tmp_path, "back")
    away, go_away = held_sensor(hosts, tmp_path, "away")

    hosts.cut(1)
    wait_for(lambda: not reachable(hosts, 1, hosts.address(0), PORT), 60, "host 1 cut off from the master")
    go_away.touch()  # its master stays away beyond the bound
    away.wait_output("reading its parameters", timeout=60)
    try:
        wait_for(lambda: not away.running(), 120, "the node whose master stays away to stop")
    except AssertionError as err:
        raise AssertionError(f"{err}\n--- its output ---\n{away.output()[-4000:]}") from None
    assert away.popen.returncode != 0, away.output()
    errors = [line for line in away.output().splitlines() if "cannot read" in line]
    assert len(errors) == 1 and hosts.address(0) in errors[0], away.output()
    assert "Traceback" not in away.output(), away.output()

    go_back.touch()  # its master comes back while it waits for the answer
    back.wait_output("reading its parameters", timeout=60)
    wait_for(lambda: connecting(hosts, 1, hosts.address(0), PORT), 60, "the node's read waiting for the master")
    hosts.heal(1)
    echo = hosts.run(0, ["rostopic", "echo", "-n", "1", "/r/inputs/back"], hosts.env(0, 0, PORT), "echo")
    echo.wait_output("data: False", timeout=120)  # it started normally: its proposition is published
    assert back.running() and "cannot read" not in back.output(), back.output()


def connecting(hosts, host: int, address: str, port: int) -> bool:
    """A TCP connection from ``host`` to ``address:port`` is being opened (SYN sent, no answer yet)."""
    out = subprocess.run(["ip", "netns", "exec", hosts.ns(host), "ss", "-tnH", "state", "syn-sent",
                          "dst", f"{address}:{port}"], capture_output=True, text=True, timeout=30).stdout
    return bool(out.strip())

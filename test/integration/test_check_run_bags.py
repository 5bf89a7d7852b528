"""check_run and controller_trace --bag on hostile recordings: corrupt bags (seeded byte flips and
truncations of a real bag) end in one error line and exit 2, never a traceback; a long recording is
read as a stream (memory does not grow with the bag); replayed header stamps that go back in time
never give negative times. No master: the bag is read from the file."""
from __future__ import annotations

import contextlib
import io
import json
import random
import tracemalloc

import pytest
from helpers import REPO_ROOT, run_script

from ltl_stack.errors import Exit

pytestmark = [pytest.mark.ros, pytest.mark.timeout(900)]

CP = REPO_ROOT / "config" / "clean_and_patrol"
SPEC, MAPPING = CP / "clean_and_patrol.structuredslugs", CP / "clean_and_patrol.yaml"
TOPIC = "/clean_and_patrol/controller_executor/state"
INPUTS = ["object", "pickup_ac", "drop_ac", "topLane_rc", "rightLane_rc", "bottomLane_rc", "leftLane_rc",
          "leftGround_rc", "rightGround_rc"]
OUTPUTS = ["pickup", "drop", "holdingObject", "sawObject", "stop", "topLane", "rightLane", "bottomLane", "leftLane",
           "leftGround", "rightGround"]


def write_bag(path, count: int, stamps_back: bool = False, repeat: int = 1) -> None:
    """A patrol between topLane and rightLane (in one, heading for the other), ``count`` states (each published ``repeat`` times, as the
    executor republishes), with header stamps going back in time when ``stamps_back``."""
    import rosbag
    import rospy
    from std_msgs.msg import String

    from ltl_stack.msg import ControllerState, PropositionValuation

    with rosbag.Bag(str(path), "w") as bag:
        for i in range(count):
            lane, heading = ("topLane", "rightLane")[i % 2], ("rightLane", "topLane")[i % 2]
            msg = ControllerState(state_id=i % 2, goal_index=i % 2, running=True, mode="normal")
            msg.header.stamp = rospy.Time(1000 - i if stamps_back else 1000 + i)
            msg.inputs = PropositionValuation(keys=INPUTS, values=[k == f"{lane}_rc" for k in INPUTS])
            msg.outputs = PropositionValuation(keys=OUTPUTS, values=[k == heading for k in OUTPUTS])
            for r in range(repeat):
                bag.write(TOPIC, msg, rospy.Time(1 + i + r * 0.01))
            bag.write("/clean_and_patrol/odom_text", String(data="x" * 200), rospy.Time(1 + i))


def check_in_process(bag, *extra: str) -> tuple[int, str, str]:
    from ltl_stack.ros import check_run

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = check_run.main([str(SPEC), str(MAPPING), str(bag), *extra])
    return code, out.getvalue(), err.getvalue()


def corrupted(data: bytes, seed: int) -> bytes:
    rng = random.Random(seed)
    if seed % 3 == 0:
        return data[:rng.randrange(len(data))]  # truncated
    buffer = bytearray(data)
    for _ in range(rng.choice((1, 4, 32))):
        buffer[rng.randrange(13, len(buffer))] = rng.randrange(256)  # past the version line
    return bytes(buffer)


@pytest.fixture(scope="module")
def good_bag(tmp_path_factory):
    path = tmp_path_factory.mktemp("bags") / "good.bag"
    write_bag(path, 40)
    return path


def test_150_corrupted_bags_give_one_line_or_a_report_never_a_traceback(good_bag, tmp_path):
    data = good_bag.read_bytes()
    refused = 0
    for seed in range(150):
        bag = tmp_path / f"corrupt_{seed}.bag"
        bag.write_bytes(corrupted(data, seed))
        code, out, err = check_in_process(bag)  # an exception would end the test here
        assert code in (Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT), (seed, code, out, err)
        if code == Exit.BAD_INPUT:
            refused += 1
            assert len(err.splitlines()) == 1 and str(bag) in err and out == "", (seed, err)
        bag.unlink()
    assert refused >= 50, refused  # most corruptions are found


@pytest.mark.parametrize("seed", [0, 4, 5, 16, 53, 101])  # 5, 16, 53, 101: tracebacks before
@pytest.mark.parametrize("tool", ["check_run", "controller_trace"])
def test_corrupted_bags_through_the_real_scripts(good_bag, tmp_path, tool, seed):
    bag = tmp_path / "corrupt.bag"
    bag.write_bytes(corrupted(good_bag.read_bytes(), seed))
    args = [str(SPEC), str(MAPPING), str(bag)] if tool == "check_run" else ["--bag", str(bag)]
    done = run_script(["rosrun", "ltl_stack", tool, *args], capture_output=True, text=True, timeout=300)
    assert "Traceback" not in done.stderr, done.stderr
    assert done.returncode in (Exit.OK, Exit.NEGATIVE, Exit.BAD_INPUT), done.stderr
    if done.returncode == Exit.BAD_INPUT:
        assert len(done.stderr.splitlines()) == 1, done.stderr


def test_a_long_recording_is_read_as_a_stream(tmp_path):
    bag = tmp_path / "long.bag"
    write_bag(bag, 1500, repeat=4)  # 6,000 state messages, as the executor republishes them
    size = bag.stat().st_size
    small = tmp_path / "short.bag"
    write_bag(small, 10)
    check_in_process(small)  # the spec's reading and its caches are not the bag's
    tracemalloc.start()
    try:
        code, out, err = check_in_process(bag)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert code == Exit.OK, out + err
    assert "1500 states" in out, out
    # rosbag's index of the bag (an entry per message) stays; every message in a list took about 7 times
    # the bag's size (22 MB for this 3.3 MB bag), now the peak is about the bag's size
    assert peak < 3 * size, (peak, size)


def test_replayed_stamps_that_go_back_give_no_negative_time(tmp_path):
    bag = tmp_path / "replayed.bag"
    write_bag(bag, 10, stamps_back=True)
    code, out, err = check_in_process(bag, "--json")
    assert code in (Exit.OK, Exit.NEGATIVE), err
    assert all(v["time"] >= 0 for v in json.loads(out)["violations"]), out
    done = run_script(["rosrun", "ltl_stack", "controller_trace", "--bag", str(bag), "--json"],
                      capture_output=True, text=True, timeout=300)
    times = [json.loads(line)["time"] for line in done.stdout.splitlines()]
    assert done.returncode == Exit.OK and len(times) == 10 and min(times) >= 0, done.stdout + done.stderr

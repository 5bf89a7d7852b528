"""Open-loop programs under speed scaling: the report says distances change; --keep-distances keeps them."""
import re
from pathlib import Path

from helpers import require_shared

from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.transfer import TransferOptions, transfer_program

SQUARE = Path(__file__).resolve().parents[2] / "data" / "transfer" / "styles" / "square_open_loop.py"


def transfer(keep):
    robots = require_shared("robots")
    return transfer_program(SQUARE.read_text(), load_profile(robots, "turtlebot"), load_profile(robots, "jackal"),
                            TransferOptions(keep_distances=True) if keep else None, filename="square.py")


def driven(text):
    """Side length (m) and turn angle (rad) the square program drives: speed x ticks / rate."""
    number = r"(-?[0-9.]+)"
    v = float(re.search(rf"forward.linear.x = {number}", text).group(1))
    w = float(re.search(rf"turn.angular.z = {number}", text).group(1))
    hz = float(re.search(rf"rate = rospy.Rate\({number}\)", text).group(1))
    return v * 10 / hz, w * 16 / hz


def test_scaling_an_open_loop_program_says_its_distances_change():
    result = transfer(keep=False)
    side, angle = driven(result.text)
    assert abs(side - 1.0) < 1e-6 and abs(angle - 1.185) < 1e-3, (side, angle)   # 0.4 m -> 1.0 m
    notes = [n for n in result.report.notes if n.startswith("open loop")]
    assert len(notes) == 1 and "linear.x x2.5" in notes[0] and "rospy.Rate(5) at line 17" in notes[0], notes


def test_keep_distances_scales_one_speed_factor_and_the_durations():
    before = driven(SQUARE.read_text())
    result = transfer(keep=True)
    after = driven(result.text)
    assert abs(after[0] - before[0]) < 1e-5 and abs(after[1] - before[1]) < 1e-5, (before, after)
    assert "rospy.sleep(0.675)" in result.text                        # 0.5 s / 0.741
    assert "client.wait_for_server(rospy.Duration(5))" in result.text    # a timeout is not a motion time
    assert any(n.startswith("open loop, distances kept") for n in result.report.notes)

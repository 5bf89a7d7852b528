"""Names followed through aliases, wrappers and every channel API of ROS 1 Python."""
import textwrap
from pathlib import Path

import pytest
from helpers import require_shared

from ltl_stack.transfer.channels import find_channels
from ltl_stack.transfer.codebase import parse_stats_file
from ltl_stack.transfer.profiles import load_profile
from ltl_stack.transfer.transfer import TransferOptions, transfer_program

STYLES = Path(__file__).resolve().parents[2] / "data" / "transfer" / "styles"


def channels(code):
    return [(c.kind, c.name.value, c.msg_type, c.line) for c in find_channels(textwrap.dedent(code))]


def transfer(program, source, target, text=None):
    robots = require_shared("robots")
    stats = parse_stats_file(require_shared("codebase", "channel_counts.yaml")).get(target)
    text = text if text is not None else (STYLES / program).read_text()
    result = transfer_program(text, load_profile(robots, source), load_profile(robots, target),
                              TransferOptions(stats=stats), filename=program)
    return text, result


def line_of(text, n):
    return text.splitlines()[n - 1].strip()


def unresolved(result):
    return {(u.line, u.what): u.reason for u in result.report.unresolved}


def test_a_type_alias_gives_the_message_type_and_the_topic_is_renamed():
    before, result = transfer("keyboard_alias.py", "jackal", "turtlebot")
    assert line_of(result.text, 15) == "self.pub = rospy.Publisher('cmd_vel_mux/input/navi', VelocityMsg, queue_size=1)"
    change = result.report.channels[0]
    assert (change.msg_type, change.original, change.replacement) == \
        ("geometry_msgs/Twist", "cmd_vel", "cmd_vel_mux/input/navi"), change


def test_wait_for_message_is_a_channel():
    _, result = transfer("obstacle_wait.py", "turtlebot", "jackal")
    assert line_of(result.text, 11) == "scan = rospy.wait_for_message('front/scan', LaserScan)"
    assert [(c.line, c.kind, c.msg_type) for c in result.report.channels][0] == (11, "topic", "sensor_msgs/LaserScan")


def test_every_channel_api_is_found_with_its_name_and_type():
    got = channels((STYLES / "channel_apis.py").read_text())
    assert got == [
        ("publisher", "cmd_vel", "geometry_msgs/Twist", 21),           # through make_publisher's call
        ("service_wait", "reset_odometry", None, 22),
        ("service_client", "reset_odometry", "std_srvs/Empty", 23),
        ("service_server", "~ready", "std_srvs/Trigger", 24),
        ("subscriber", "scan", "sensor_msgs/LaserScan", 25),           # message_filters.Subscriber
        ("subscriber", "odom", "nav_msgs/Odometry", 26),               # a get_param default via self.<attr>
        ("action_server", "go_to", "move_base_msgs/MoveBaseAction", 28),
        ("publisher", None, "geometry_msgs/Twist", 32),                # get_param without a default
        ("frame", "odom", None, 35), ("frame", "base_footprint", None, 35),
    ], got


def test_a_wrapper_is_followed_to_each_call_and_the_call_site_is_edited():
    code = textwrap.dedent("""\
        import rospy
        from geometry_msgs.msg import Twist
        def advertise(name, queue=1):
            return rospy.Publisher(name, Twist, queue_size=queue)
        a = advertise('cmd_vel')
        b = advertise(name='cmd_vel', queue=5)
    """)
    _, result = transfer("wrapper.py", "jackal", "turtlebot", code)
    assert [line_of(result.text, n) for n in (4, 5, 6)] == [
        "return rospy.Publisher(name, Twist, queue_size=queue)",
        "a = advertise('cmd_vel_mux/input/navi')",
        "b = advertise(name='cmd_vel_mux/input/navi', queue=5)"], result.text
    assert not result.report.unresolved, result.report.unresolved


def test_what_cannot_be_followed_is_unresolved_never_everything_resolved():
    _, result = transfer("channel_apis.py", "turtlebot", "jackal")
    got = unresolved(result)
    assert "parameter '~cmd_topic' (no default" in got[(32, "topic name")], got
    assert "no URDF for jackal" in got[(35, "tf frame 'base_footprint'")], got
    assert "no service of type Empty" in got[(23, "service 'reset_odometry'")], got
    assert "no service of type Empty" in got[(22, "service 'reset_odometry'")], got   # wait_for_service: the proxy's type
    assert not any(line == 24 for line, _ in got), "a private name belongs to the program's own node"
    assert "Everything was resolved" not in result.report.to_text()
    assert line_of(result.text, 25) == "scan = message_filters.Subscriber('front/scan', LaserScan)"


def test_a_get_param_default_is_rewritten_and_flagged():
    code = textwrap.dedent("""\
        import rospy
        from geometry_msgs.msg import Twist
        topic = rospy.get_param('~cmd_vel_topic', 'cmd_vel')
        pub = rospy.Publisher(topic, Twist, queue_size=1)
    """)
    _, result = transfer("param.py", "jackal", "turtlebot", code)
    assert line_of(result.text, 3) == "topic = rospy.get_param('~cmd_vel_topic', 'cmd_vel_mux/input/navi')"
    assert "default of the parameter '~cmd_vel_topic'" in result.report.channels[0].flagged


def test_tf_frames_are_checked_against_the_target_urdf():
    code = textwrap.dedent("""\
        import rospy, tf
        listener = tf.TransformListener()
        listener.waitForTransform('base_link', 'head_camera_link', rospy.Time(), rospy.Duration(1.0))
    """)
    _, result = transfer("frames.py", "fetch", "pr2", code)
    got = unresolved(result)
    assert list(got) == [(3, "tf frame 'head_camera_link'")], got
    assert "pr2's URDF has no link 'head_camera_link'" in got[(3, "tf frame 'head_camera_link'")]


@pytest.mark.parametrize("call", ["node.create_publisher(Twist, 'cmd_vel', 10)",
                                  "actionlib.ActionClient('move_base', MoveBaseAction)"])
def test_a_channel_api_not_followed_is_listed(call):
    code = f"import rospy, actionlib\nfrom geometry_msgs.msg import Twist\nx = {call}\n"
    _, result = transfer("other_api.py", "jackal", "turtlebot", code)
    assert [u.line for u in result.report.unresolved] == [3], result.report.unresolved
    assert "not followed" in result.report.unresolved[0].reason

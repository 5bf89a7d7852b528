"""action_proposition (activation-completion over actionlib) against the simulated servers."""
from __future__ import annotations

import pytest
from helpers import require_shared, wait_for
from test_nodes_probe import make_session

pytestmark = [pytest.mark.ros, pytest.mark.timeout(300)]  # a hang guard, far above the waits

ACTIVE, PREEMPTED, SUCCEEDED, ABORTED = 1, 2, 3, 4


@pytest.fixture
def ros(request):
    return make_session(request)


def statuses(msg) -> list[int]:
    return [s.status for s in msg.status_list]


def test_rising_edge_sends_a_goal_completion_follows_the_result_and_resets_on_falling_edge(ros):
    from std_msgs.msg import Bool

    completion = ros.record(ros.topic("inputs/pickup_ac"), Bool)
    ros.run("sim_manipulation_server", "_duration:=0.5", f"__ns:={ros.ns}")
    ros.run("action_proposition", f"_action:={ros.topic('pick')}", "_rate:=20",
            f"proposition:={ros.topic('outputs/pickup')}", f"completion:={ros.topic('inputs/pickup_ac')}")
    ros.set_bool(ros.topic("outputs/pickup"), False)
    completion.wait_last(lambda b: b.data is False, what="completion false before activation")
    ros.master.wait_for_subscriber(ros.topic("pick/result"))

    ros.set_bool(ros.topic("outputs/pickup"), True)
    completion.wait_last(lambda b: b.data is True, what="completion after the pick")
    ros.set_bool(ros.topic("outputs/pickup"), False)
    completion.wait_last(lambda b: b.data is False, what="completion reset on the falling edge")
    values = [b.data for b in completion.snapshot()]
    changes = [v for i, v in enumerate(values) if i == 0 or v != values[i - 1]]
    assert changes == [False, True, False], changes


def test_falling_edge_cancels_a_running_goal(ros):
    from actionlib_msgs.msg import GoalStatusArray
    from std_msgs.msg import Bool

    status = ros.record(ros.topic("drop/status"), GoalStatusArray)
    completion = ros.record(ros.topic("drop_ac"), Bool)
    ros.run("sim_manipulation_server", "_duration:=10", f"__ns:={ros.ns}")
    ros.run("action_proposition", f"_action:={ros.topic('drop')}",
            f"_proposition_topic:={ros.topic('outputs/drop')}", f"_completion_topic:={ros.topic('drop_ac')}")
    ros.master.wait_for_subscriber(ros.topic("drop/result"))
    ros.set_bool(ros.topic("outputs/drop"), True)
    status.wait_last(lambda m: statuses(m) == [ACTIVE], what="the drop goal running")
    ros.set_bool(ros.topic("outputs/drop"), False)
    status.wait_last(lambda m: statuses(m) == [PREEMPTED], what="the drop goal preempted")
    assert all(b.data is False for b in completion.snapshot()), completion.snapshot()


def test_aborted_goal_is_retried_while_activated_and_the_server_may_come_later(ros):
    from std_msgs.msg import Bool

    from ltl_stack.msg import PropositionActionGoal

    goals = ros.record(ros.topic("wave/goal"), PropositionActionGoal)
    completion = ros.record(ros.topic("wave_ac"), Bool)
    ros.run("action_proposition", f"_action:={ros.topic('wave')}", "_retry_delay:=0.2",
            f"proposition:={ros.topic('outputs/wave')}", f"completion:={ros.topic('wave_ac')}")
    ros.set_bool(ros.topic("outputs/wave"), True)  # activated before the server exists
    ros.run("sim_manipulation_server", "_duration:=0.2", "_actions:=[wave]", "_fail:=[wave]", f"__ns:={ros.ns}")
    goals.wait(lambda ms: len(ms) >= 3, what="the goal sent three times")
    ids = {g.goal_id.id for g in goals.snapshot()}
    assert len(ids) == len(goals.snapshot()), ids  # each retry is a new goal
    assert all(b.data is False for b in completion.snapshot()), "a failed action reported completion"


def test_navigation_goal_from_params_reaches_the_region(ros):
    from std_msgs.msg import Bool, String

    from ltl_stack.runtime.propositions.regions import RegionMap

    path = require_shared("specs", "move_group_and_move_base", "lab_loop.regions")
    start = RegionMap.load(path, scale=0.005).find("left_ground").interior_point()
    topics = [f"{n}:={ros.topic(n)}" for n in ("cmd_vel", "odom", "pose", "current_region")]
    region = ros.record(ros.topic("current_region"), String)
    completion = ros.record(ros.topic("inputs/rightGround_done"), Bool)
    regions = [f"_regions_file:={path}", "_scale:=0.005"]
    ros.run("sim_robot", "_mode:=holonomic", f"_x:={start[0]}", f"_y:={start[1]}", "_time_scale:=4",
            *regions, *topics)
    ros.run("sim_navigation_server", "_mode:=holonomic", f"_action:={ros.topic('navigate')}", *regions, *topics)
    ros.run("action_proposition", f"_action:={ros.topic('navigate')}", "_action_type:=ltl_stack/NavigateAction",
            "_goal:={region: rightGround}", f"proposition:={ros.topic('outputs/rightGround')}",
            f"completion:={ros.topic('inputs/rightGround_done')}")
    ros.master.wait_for_subscriber(ros.topic("navigate/result"))
    region.wait_last(lambda s: s.data == "left_ground", what="the robot in left_ground")
    ros.set_bool(ros.topic("outputs/rightGround"), True)
    completion.wait_last(lambda b: b.data is True, timeout=60, what="navigation completed")
    assert region.last().data == "right_ground", region.last()


def test_bad_goal_for_the_action_type_is_one_clear_error(ros):
    node = ros.run("action_proposition", "_action:=/navigate", "_action_type:=ltl_stack/Navigate",
                   "_goal:={room: kitchen}")
    wait_for(lambda: not node.running(), 90, "the node to exit")
    out = node.output()
    assert node.popen.returncode == 2, out
    assert "~goal {'room': 'kitchen'} does not fit ltl_stack/NavigateGoal" in out, out
    assert "Traceback" not in out, out


def test_shutdown_while_active_cancels_the_goal(ros):
    from actionlib_msgs.msg import GoalStatusArray

    status = ros.record(ros.topic("pick/status"), GoalStatusArray)
    ros.run("sim_manipulation_server", "_duration:=10", f"__ns:={ros.ns}")
    node = ros.run("action_proposition", f"_action:={ros.topic('pick')}",
                   f"proposition:={ros.topic('outputs/pickup')}", f"completion:={ros.topic('pickup_ac')}")
    ros.master.wait_for_subscriber(ros.topic("pick/result"))
    ros.set_bool(ros.topic("outputs/pickup"), True)
    status.wait_last(lambda m: statuses(m) == [ACTIVE], what="the pick goal running")
    assert node.stop() == 0, node.output()
    status.wait_last(lambda m: statuses(m) == [PREEMPTED], what="the pick goal cancelled on shutdown")


def test_a_goal_ended_before_send_goal_returns_still_reaches_the_client(ros):
    """actionlib's SimpleActionClient takes the new goal's handle only after publishing the goal; a
    result handled before that was dropped ("a goal handle that we're not tracking") and the client
    waited out its timeout (seen in a loaded suite run). Here send_goal is held until this process has
    received the server's result, the widest form of that window; our client must still see it."""
    import time

    import rospy

    from ltl_stack.msg import NavigateAction, NavigateActionResult, NavigateGoal
    from ltl_stack.ros.action_client import SimpleActionClient

    # Recorded before the client subscribes: rospy calls the recorder before actionlib's callback.
    results = ros.record(ros.topic("navigate/result"), NavigateActionResult)
    ros.run("sim_navigation_server", f"_action:={ros.topic('navigate')}", "_mode:=holonomic")  # no regions
    client = ros.action_client(ros.topic("navigate"), NavigateAction, timeout=90)
    assert isinstance(client, SimpleActionClient)
    manager = client.action_client.manager
    publish = manager.send_goal_fn

    def publish_and_hold(action_goal) -> None:
        publish(action_goal)
        results.wait(lambda msgs: [m for m in msgs if m.status.goal_id.id == action_goal.goal_id.id], 90,
                     "the server's result")
        time.sleep(0.3)  # lets actionlib's callbacks run now, inside the window (they must not be lost)

    manager.send_goal_fn = publish_and_hold
    done: list = []
    client.send_goal(NavigateGoal(region="kitchen"), done_cb=lambda state, result: done.append(state))
    assert results.snapshot(), "send_goal returned before the result arrived"
    assert client.wait_for_result(rospy.Duration(60)), "the result was lost"
    assert client.get_state() == ABORTED, client.get_state()
    assert "no ~regions_file" in client.get_goal_status_text(), client.get_goal_status_text()
    wait_for(lambda: done == [ABORTED], 60, "done_cb with ABORTED")

"""The controller view tells the truth about the executor it shows (offscreen, pytest-qt, real master,
real ``controller_executor`` processes): it draws the spec the executor runs and follows a restart with
another spec, greys itself when the executor dies, clears what it showed when an Attach fails or is
cancelled, and shows violations reported as WARN (recovered) as well as ERROR."""
from __future__ import annotations

import os
import signal
import uuid

import pytest
from helpers import wait_for
from test_nodes_probe import shared_master

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("pytestqt")

from ltl_stack.gui.controller_view import ControllerView  # noqa: E402

pytestmark = [pytest.mark.ros, pytest.mark.slow]

WAIT = 90_000  # ms

SPEC_A = """\
[INPUT]
person
door

[OUTPUT]
move
stop

[ENV_TRANS]
!(person' & door')

[SYS_TRANS]
person' -> stop'
!person' -> move'
!(move' & stop')
"""
# another automaton: one more output, lit with a person
SPEC_B = SPEC_A.replace("stop\n\n[ENV_TRANS]", "stop\nlight\n\n[ENV_TRANS]") + "person' <-> light'\n"


class Executor:
    """One ``controller_executor`` in namespace ``ns`` on the shared master, its inputs published
    (latched) from this process."""

    def __init__(self, master, ns: str) -> None:
        self.master, self.ns, self.process = master, ns, None
        self._pubs = {}

    @property
    def state(self) -> str:
        return f"{self.ns}/controller_executor/state"

    def start(self, spec) -> None:
        self.process = self.master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), f"__ns:={self.ns}"],
                                       name=f"executor_{self.ns.strip('/')}")
        self.master.wait_for_publisher(self.state, timeout=120)

    def set(self, **values: bool) -> None:
        import rospy
        from std_msgs.msg import Bool

        for name, value in values.items():
            topic = f"{self.ns}/inputs/{name}"
            if topic not in self._pubs:
                self._pubs[topic] = rospy.Publisher(topic, Bool, queue_size=10, latch=True)
            self._pubs[topic].publish(Bool(data=value))

    def kill(self) -> None:
        os.killpg(self.process.popen.pid, signal.SIGKILL)
        self.process.popen.wait(30)

    def stop(self) -> None:
        if self.process is not None:
            self.process.stop()

    def close(self) -> None:
        self.stop()
        for pub in self._pubs.values():
            pub.unregister()


@pytest.fixture
def executor(monkeypatch):
    master = shared_master()
    monkeypatch.setenv("ROS_MASTER_URI", master.uri)  # rospy's service lookups read it, as in a real host
    ex = Executor(master, f"/gv_{uuid.uuid4().hex[:8]}")
    yield ex
    ex.close()


@pytest.fixture
def specs(tmp_path):
    a, b = tmp_path / "a.structuredslugs", tmp_path / "b.structuredslugs"
    a.write_text(SPEC_A)
    b.write_text(SPEC_B)
    return a, b


def attached(qtbot, ex: Executor, spec) -> ControllerView:
    view = ControllerView()
    qtbot.addWidget(view)
    view.spec_line_edit.setText(str(spec))
    view.topic_combo_box.setEditText(ex.state)
    view.attach_push_button.click()
    qtbot.waitUntil(lambda: view.model is not None and view.model.current is not None, timeout=WAIT)
    return view


def test_the_view_follows_an_executor_restarted_with_another_spec(qtbot, executor, specs):
    a, b = specs
    executor.set(person=False, door=False)
    executor.start(a)
    view = attached(qtbot, executor, a)
    assert view.model.spec_path == str(a) and view.banner_label.isHidden()
    assert view.model.source is not None and view.model.source.spec.spec_file == str(a)
    executor.stop()
    executor.set(person=True, door=False)
    executor.start(b)
    # the executor now runs b: the view draws b (the executor's own file) and says a is not what runs
    qtbot.waitUntil(lambda: view.model is not None and view.model.spec_path == str(b), timeout=WAIT)
    qtbot.waitUntil(lambda: view.banner_label.isVisible() or not view.banner_label.isHidden(), timeout=WAIT)
    assert str(a) in view.banner_label.text() and str(b) in view.banner_label.text()
    qtbot.waitUntil(lambda: view.model.current is not None and view.shown is not None
                    and view.shown.inputs.get("person"), timeout=WAIT)
    state = view.model.automaton.states[view.model.current]
    assert state.outputs["stop"] and state.outputs["light"] and view.state_label.text().startswith(f"state {state.id} ")
    # greyed while no executor published (the restart took more than a few seconds), lit once heard again
    qtbot.waitUntil(lambda: view.alive and view.lamp_values()["light"], timeout=WAIT)
    view.shutdown()


def test_a_killed_executor_greys_the_view_and_disables_pause(qtbot, executor, specs):
    a, _ = specs
    executor.set(person=False, door=False)
    executor.start(a)
    view = attached(qtbot, executor, a)
    qtbot.waitUntil(lambda: view.alive and view.run_pause_push_button.isEnabled(), timeout=WAIT)
    assert any(view.lamp_values().values())  # move is lit
    assert "last state" in view.liveness_label.text()
    executor.kill()
    qtbot.waitUntil(lambda: not view.alive, timeout=WAIT)
    assert not view.run_pause_push_button.isEnabled()
    assert not any(view.lamp_values().values()), view.lamp_values()
    assert view.graph_opacity.opacity() < 1.0
    assert "not heard from" in view.mode_label.text() and "last state" in view.liveness_label.text()
    view.shutdown()


def test_a_failed_or_cancelled_attach_clears_what_was_shown(qtbot, executor, specs):
    a, _ = specs
    executor.set(person=False, door=False)
    executor.start(a)
    view = attached(qtbot, executor, a)
    qtbot.waitUntil(lambda: view.state_label.text().startswith("state "), timeout=WAIT)
    view.strategy_label.setText("strategy 1: something")  # as after a resynthesis of the first executor
    # another robot's topic with no executor, and a spec that does not exist: the attach fails
    view.spec_line_edit.setText(str(a.parent / "missing.structuredslugs"))
    view.topic_combo_box.setEditText(f"{executor.ns}_none/controller_executor/state")
    view.attach_push_button.click()
    assert view.state_label.text() == "state: —" and view.strategy_label.text() == ""
    qtbot.waitUntil(lambda: "Cannot attach" in view.status_label.text(), timeout=WAIT)
    assert view.model is None and view.state_label.text() == "state: —" and view.lamp_values() == {}
    assert view.strategy_label.text() == "" and not view.run_pause_push_button.isEnabled()
    assert view.mode_label.text() == "mode: not attached"
    # attach again to the running executor, then to the missing one, cancelled meanwhile
    view.spec_line_edit.setText(str(a))
    view.topic_combo_box.setEditText(executor.state)
    view.attach_push_button.click()
    qtbot.waitUntil(lambda: view.model is not None and view.model.current is not None, timeout=WAIT)
    view.topic_combo_box.setEditText(f"{executor.ns}_none/controller_executor/state")
    view.attach_push_button.click()
    assert view.cancel()
    assert view.state_label.text() == "state: —" and view.lamp_values() == {} and view.model is None
    assert "Cancelled" in view.status_label.text() and not view.run_pause_push_button.isEnabled()
    view.shutdown()


def test_a_recovered_violation_reported_as_warn_is_shown(qtbot, executor, specs):
    a, _ = specs
    executor.set(person=False, door=False)
    executor.start(a)
    view = attached(qtbot, executor, a)
    executor.set(person=True, door=True)  # breaks !(person & door); recovery (the default) answers: a WARN
    qtbot.waitUntil(lambda: view.shown is not None and view.shown.violations >= 1, timeout=WAIT)
    qtbot.waitUntil(lambda: "[WARN]" in view.violation_text.toPlainText(), timeout=WAIT)
    assert view.statuses["environment assumptions"][0] == 1
    text = view.violation_text.toPlainText()
    assert "person" in text and "door" in text, text
    executor.set(person=False, door=False)
    qtbot.waitUntil(lambda: "cleared" in view.violation_text.toPlainText(), timeout=WAIT)
    view.shutdown()


def test_the_executor_publishes_what_it_runs(executor, specs):
    """``~source`` (latched): the spec's path, SHA-256 and text, the generation and the options."""
    import hashlib

    import rospy

    from ltl_stack.msg import ControllerSource

    a, _ = specs
    executor.set(person=False, door=False)
    executor.start(a)
    got = []
    sub = rospy.Subscriber(f"{executor.ns}/controller_executor/source", ControllerSource, got.append)
    try:
        wait_for(lambda: got, 60, "a ~source message")
    finally:
        sub.unregister()
    msg = got[0]
    assert (msg.spec_file, msg.spec_text, msg.strategy_generation) == (str(a), SPEC_A, 0)
    assert msg.spec_sha256 == hashlib.sha256(SPEC_A.encode()).hexdigest()
    assert msg.robotics_semantics and msg.cooperative and msg.started.to_sec() > 0


def test_the_view_greys_when_the_master_goes_away(tmp_path, specs):
    """The master dies, the executor lives on (its state and diagnostics still reach the view, peer to
    peer): the view says that no master answers, greys itself and disables Pause. In a process of its
    own, as rospy binds a process to one master."""
    import json
    import subprocess
    import sys
    from pathlib import Path

    from helpers import RosMaster

    a, _ = specs
    (tmp_path / "master").mkdir()
    master = RosMaster(tmp_path / "master")
    try:
        ns = "/gm"
        master.run(["rosrun", "ltl_stack", "controller_executor", str(a), f"__ns:={ns}"], name="executor_gm")
        master.wait_for_publisher(f"{ns}/controller_executor/source", timeout=120)
        helper = Path(__file__).with_name("gui_master_gone.py")
        view = subprocess.Popen([sys.executable, str(helper), f"{ns}/controller_executor/state"], env=master.env,
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            line = view.stdout.readline()
            assert line.strip() == "attached", line + view.stderr.read()[-3000:]
            master._master.stop()  # the master only: the executor keeps running
            view.stdin.write("gone\n")
            view.stdin.flush()
            shown = json.loads(view.stdout.readline())
            assert view.wait(60) == 0, shown
        finally:
            if view.poll() is None:
                view.kill()
                view.wait(30)
        assert not shown["alive"] and not shown["pause_enabled"] and shown["opacity"] < 1.0, shown
        assert "no ROS master answers" in shown["liveness"], shown
    finally:
        master.shutdown()


def test_before_the_first_state_the_view_says_what_the_executor_says(qtbot, executor, specs):
    """The view shows the executor's words, not always "waiting for every input to report (ready
    handshake)". The executor names the input it waits for, and says when it is paused: the view shows its words."""
    a, _ = specs
    executor.set(person=False)  # door never reports
    executor.start(a)
    view = ControllerView()
    qtbot.addWidget(view)
    view.topic_combo_box.setEditText(executor.state)  # no spec named: the executor's own is drawn
    view.attach_push_button.click()
    qtbot.waitUntil(lambda: view.model is not None and view.shown is not None, timeout=WAIT)
    assert view.model.spec_path == str(a) and view.shown.state_id < 0
    qtbot.waitUntil(lambda: "waiting for input(s) door" in view.mode_label.text(), timeout=WAIT)
    assert "ready handshake" not in view.mode_label.text()
    qtbot.waitUntil(lambda: view.run_pause_push_button.isEnabled(), timeout=WAIT)
    view.run_pause_push_button.click()  # pause through ~set_running
    qtbot.waitUntil(lambda: "paused" in view.mode_label.text(), timeout=WAIT)
    assert "waiting" not in view.mode_label.text(), view.mode_label.text()
    view.shutdown()

"""The three panels offscreen (pytest-qt) against a real master running the clean-and-patrol scenario
(launch/clean_and_patrol.launch: simulated robot, proposition nodes, executor), and thesis Example 7's
apply-and-check on the simple scenario's live graph."""
from __future__ import annotations

import os

import pytest
from helpers import REPO_ROOT
from test_nodes_probe import shared_master

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
pytest.importorskip("pytestqt")

from pytestqt.exceptions import TimeoutError as QtTimeoutError  # noqa: E402

from ltl_stack.gui.analysis_panel import AnalysisPanel  # noqa: E402
from ltl_stack.gui.controller_view import ControllerView  # noqa: E402
from ltl_stack.gui.mapping_model import INPUT, OUTPUT  # noqa: E402
from ltl_stack.gui.mapping_panel import MappingPanel  # noqa: E402
from ltl_stack.runtime.config.mapping import load_mapping  # noqa: E402

pytestmark = [pytest.mark.ros, pytest.mark.slow]

CONFIG = REPO_ROOT / "config"
SPEC = CONFIG / "clean_and_patrol" / "clean_and_patrol.structuredslugs"
MAPPING = CONFIG / "clean_and_patrol" / "clean_and_patrol.yaml"
STATE = "/clean_and_patrol/controller_executor/state"
REGIONS = ["topLane", "rightLane", "bottomLane", "leftLane", "leftGround", "rightGround"]
WAIT = 90_000  # ms
LOAD_WAIT = 300_000  # ms: a scenario's start and the view's own synthesis of its spec, on a busy machine


@pytest.fixture(scope="module")
def scenario():
    """clean_and_patrol.launch on the process's shared master, up to the executor's first state."""
    master = shared_master()
    launch = master.run(["roslaunch", "ltl_stack", "clean_and_patrol.launch"], name="gui_clean_and_patrol")
    try:
        master.wait_for_publisher(STATE, timeout=120)
        for prop in ("object", "rightGround_rc"):
            master.wait_for_publisher(f"/clean_and_patrol/inputs/{prop}", timeout=60)
        master.wait_for_subscriber("/clean_and_patrol/outputs/rightGround", timeout=60)
        master.wait_for_subscriber("/clean_and_patrol/cmd_vel", timeout=60)
    except AssertionError as err:
        launch.stop()
        raise AssertionError(f"{err}\n{launch.output()[-4000:]}") from None
    yield master
    launch.stop()


def master_nodes(master) -> list[str]:
    pubs, subs, services = master.system_state()
    return sorted({n for _name, nodes in (*pubs, *subs, *services) for n in nodes})


def test_mapping_panel_on_the_live_scenario(scenario, qtbot, tmp_path):
    panel = MappingPanel()
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SPEC))
    panel.mapping_line_edit.setText(str(MAPPING))
    panel.master_line_edit.setText(scenario.uri)
    panel.load_push_button.click()
    assert panel.doc is not None, panel.status_label.text()
    panel.refresh_push_button.click()
    qtbot.waitUntil(lambda: panel.graph is not None, timeout=WAIT)
    combo = panel.combo(INPUT, "object", 0, "node")
    assert [combo.itemText(i) for i in range(combo.count())] == master_nodes(scenario)
    pubs = scenario.system_state()[0]
    published = sorted(t for t, nodes in pubs if "/clean_and_patrol/object" in nodes)
    topic = panel.combo(INPUT, "object", 0, "topic")
    assert [topic.itemText(i) for i in range(topic.count())] == published
    out_topic = panel.combo(OUTPUT, "rightGround", 0, "topic")
    assert "/clean_and_patrol/outputs/rightGround" in [out_topic.itemText(i) for i in range(out_topic.count())]
    assert [f for f in panel.findings if f.severity == "error"] == [], [str(f) for f in panel.findings]
    # edit: an input on the camera's Float64 topic is wrong twice over
    combo.setEditText("/clean_and_patrol/camera")
    topic.setEditText("/clean_and_patrol/camera/object_distance")
    qtbot.waitUntil(lambda: any("std_msgs/Float64" in f.message for f in panel.findings), timeout=WAIT)
    combo.setEditText("/clean_and_patrol/object")
    topic.setEditText("/clean_and_patrol/inputs/object")
    panel.findChild(type(panel.refresh_push_button), "stop_add_push_button").click()
    panel.combo(OUTPUT, "stop", 1, "node").setEditText("/clean_and_patrol/sim_robot")
    qtbot.waitUntil(lambda: not any(f.severity == "error" for f in panel.findings), timeout=WAIT)
    out = tmp_path / "edited.yaml"
    assert panel.save(str(out)), panel.status_label.text()
    saved, original = load_mapping(out), load_mapping(MAPPING)
    assert saved.inputs["object"][0].node == "/clean_and_patrol/object"
    assert (saved.inputs["object"][0].parameters, saved.inputs["object"][0].filename) == (
        original.inputs["object"][0].parameters, original.inputs["object"][0].filename)
    assert [e.node for e in saved.outputs["stop"]] == ["stop", "/clean_and_patrol/sim_robot"]
    panel.load_push_button.click()
    assert panel.combo(OUTPUT, "stop", 1, "node").currentText() == "/clean_and_patrol/sim_robot"
    assert panel.combo(INPUT, "object", 0, "node").currentText() == "/clean_and_patrol/object"


def test_mapping_panel_save_keeps_what_it_did_not_edit_and_asks_about_changes_on_disk(scenario, qtbot, tmp_path):
    """Save keeps expected_feedback: and every comment, and never overwrites edits made on disk."""
    mapping = tmp_path / "clean_and_patrol.yaml"
    original = MAPPING.read_text()
    mapping.write_text(original)
    panel = MappingPanel()
    qtbot.addWidget(panel)
    asked = []
    panel.confirm = lambda title, text: asked.append(title) or False  # the user answers No
    panel.spec_line_edit.setText(str(SPEC))
    panel.mapping_line_edit.setText(str(mapping))
    panel.master_line_edit.setText(scenario.uri)
    panel.load_push_button.click()
    panel.refresh_push_button.click()
    qtbot.waitUntil(lambda: panel.graph is not None, timeout=WAIT)
    panel.save_push_button.click()
    assert mapping.read_text() == original and asked == []  # no edit: the file as it was
    combo = panel.combo(OUTPUT, "stop", 0, "node")
    combo.setEditText("/clean_and_patrol/sim_robot")
    panel.save_push_button.click()
    saved = mapping.read_text()
    assert [line for line in saved.splitlines() if line.lstrip().startswith("#")] == \
        [line for line in original.splitlines() if line.lstrip().startswith("#")]
    again, before = load_mapping(mapping), load_mapping(MAPPING)
    assert again.expected_feedback == before.expected_feedback and again.namespace == before.namespace
    assert again.outputs["stop"][0].node == "/clean_and_patrol/sim_robot"
    assert saved.replace("'/clean_and_patrol/sim_robot'", "'stop'", 1) == original or \
        saved.replace("/clean_and_patrol/sim_robot", "'stop'", 1) == original
    # someone edits the file on disk; Save asks, and No leaves their edit alone
    mapping.write_text(saved + "# added in another editor\n")
    combo.setEditText("stop")
    panel.save_push_button.click()
    assert asked == ["File changed on disk"] and mapping.read_text().endswith("# added in another editor\n")
    assert "changed on disk" in panel.status_label.text()
    panel.confirm = lambda title, text: asked.append(title) or True  # Yes: overwrite
    panel.save_push_button.click()
    assert asked[-1] == "File changed on disk" and mapping.read_text() == original


def test_analysis_panel_on_the_live_scenario(scenario, qtbot):
    panel = AnalysisPanel()
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SPEC))
    panel.mapping_line_edit.setText(str(MAPPING))
    panel.live_check_box.setChecked(True)
    panel.master_line_edit.setText(scenario.uri)
    panel.analyze_push_button.click()
    qtbot.waitUntil(lambda: panel.result is not None or "rror" in panel.status_label.text(), timeout=WAIT)
    assert panel.result is not None, panel.status_label.text()
    e2 = panel.tables["E2"]
    first = [row for row, f in zip(e2.rows, e2.finding) if f == 0]
    assert first[0][0] == "[/clean_and_patrol/cmd_vel]" and {r[1] for r in first} == {"stop", *REGIONS}
    assert panel.selected_rows("E2") == e2.rows_of(0) or panel.current_key() == "E1"
    text = panel.suggestions_text.toPlainText()
    assert "stop, topLane, rightLane, bottomLane, leftLane, leftGround and rightGround are mutually exclusive" in text
    qtbot.waitUntil(lambda: panel.graph_view.graph is not None, timeout=WAIT)  # laid out off the GUI thread
    assert panel.graph_view.items


def test_apply_and_check_shows_example_7_unrealizable_on_the_live_simple_graph(ros_master, qtbot, tmp_path):
    launch = ros_master.run(["roslaunch", "ltl_stack", "simple.launch", "start_executor:=false"], name="simple")
    for topic in ("/simple/outputs/move", "/simple/outputs/stop"):
        ros_master.wait_for_subscriber(topic, timeout=60)
    ros_master.wait_for_publisher("/simple/cmd_vel", timeout=60)
    ros_master.wait_for_publisher("/simple/inputs/person", timeout=60)
    panel = AnalysisPanel()
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(CONFIG / "simple" / "simple.structuredslugs"))
    panel.mapping_line_edit.setText(str(CONFIG / "simple" / "simple.yaml"))
    panel.live_check_box.setChecked(True)
    panel.master_line_edit.setText(ros_master.uri)
    panel.analyze()
    qtbot.waitUntil(lambda: panel.result is not None or "rror" in panel.status_label.text(), timeout=WAIT)
    assert panel.result is not None, panel.status_label.text() + launch.output()[-2000:]
    assert [r[1] for r in panel.tables["E2"].rows[:2]] == ["move", "stop"]
    panel.amended_line_edit.setText(str(tmp_path / "simple_amended.slugsin"))
    panel.apply_push_button.click()
    qtbot.waitUntil(lambda: panel.applied is not None, timeout=WAIT)
    assert panel.verdict_label.text().startswith("UNREALIZABLE")
    text = panel.apply_text.toPlainText()
    assert "simple.structuredslugs:" in text and "move'" in text and "person' -> stop'" in text


def test_controller_view_follows_the_executor_and_pauses_it(scenario, qtbot, monkeypatch):
    monkeypatch.setenv("ROS_MASTER_URI", scenario.uri)  # rospy's service lookups read it, as in a real host
    view = ControllerView()
    qtbot.addWidget(view)
    view.spec_line_edit.setText(str(SPEC))
    view.refresh_push_button.click()  # the master is asked off the GUI thread
    qtbot.waitUntil(lambda: view.topic_combo_box.findText(STATE) >= 0, timeout=WAIT)
    view.topic_combo_box.setEditText(STATE)
    assert view.attach()
    qtbot.waitUntil(lambda: view.model is not None and view.model.current is not None, timeout=WAIT)
    seen, lost = [], []

    def moved_three_times():
        current = view.model.current
        if view.shown is not None and view.shown.state_id >= 0 and current is None:
            lost.append(view.shown)
        if current is not None and (not seen or seen[-1] != current):
            seen.append(current)
        return len(seen) >= 4
    qtbot.waitUntil(moved_three_times, timeout=WAIT)
    # With recovery on (the executor's default), a reading that breaks an environment assumption for a
    # moment (two region messages on their way) may move the executor to a safe position outside the
    # exported automaton, published with its symbolic id; its next step returns to the automaton
    # (runtime.executor.recovery). The view must place every other state.
    a = view.model.automaton
    n = len(a.inputs) + len(a.outputs)
    for update in lost:
        bits = [bool(update.state_id >> k & 1) for k in range(n)]
        assert update.state_id >> n == update.goal, f"executor state not found in the automaton: {update}"
        assert a.find(dict(zip(a.inputs, bits)), dict(zip(a.outputs, bits[len(a.inputs):])),
                      update.goal) is None, f"the automaton has this executor state, the view missed it: {update}"
    qtbot.waitUntil(lambda: view.current_node_id() is not None and bool(view.graph_view._marks), timeout=WAIT)
    state = view.model.automaton.states[view.model.current]
    assert view.state_label.text().startswith(f"state {state.id} ")
    # pause through ~set_running: the executor reports itself paused with every output false
    assert view.run_pause_push_button.text() == "Pause"
    view.run_pause_push_button.click()
    qtbot.waitUntil(lambda: view.shown is not None and not view.shown.running
                    and not any(view.shown.outputs.values()), timeout=WAIT)
    assert view.run_pause_push_button.text() == "Run" and "paused" in view.mode_label.text()
    assert not any(v for name, v in view.lamp_values().items() if name in view.model.automaton.outputs)
    view.run_pause_push_button.click()
    qtbot.waitUntil(lambda: view.shown is not None and view.shown.running, timeout=WAIT)
    assert view.run_pause_push_button.text() == "Pause"
    view.shutdown()


@pytest.mark.timeout(1200)  # a whole scenario beside the view's own synthesis, on a busy machine
def test_controller_view_follows_alices_resynthesis(qtbot, tmp_path, monkeypatch):
    """Live: thesis Example 11's alice characterizes the broken door; the view shows
    the resilience mode and counters and loads the characterized spec the executor reports on ~state."""
    import subprocess
    import sys

    master = shared_master()
    monkeypatch.setenv("ROS_MASTER_URI", master.uri)
    characterized = tmp_path / "alice_characterized.structuredslugs"
    demo = subprocess.Popen([sys.executable, "-m", "ltl_stack.sim.demo", "--scenario", "alice_ec", "--json",
                             "--timeout", "400", "--master-uri", master.uri,
                             "--launch-arg", f"executor_args:=--characterized-spec {characterized}"],
                            cwd=REPO_ROOT, env=master.env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        state = "/alice/controller_executor/state"
        master.wait_for_publisher(state, timeout=120)
        view = ControllerView()
        qtbot.addWidget(view)
        view.spec_line_edit.setText(str(CONFIG / "alice" / "alice.structuredslugs"))
        view.topic_combo_box.setEditText(state)
        assert view.attach()
        # the view synthesizes the executor's spec itself before it shows a state: minutes on a busy machine
        qtbot.waitUntil(lambda: view.model is not None and view.shown is not None, timeout=LOAD_WAIT)

        def characterized_strategy_loaded_and_a_state_shown() -> bool:
            # after loading the new strategy the view shows the next state it is given, a tick later
            model, shown = view.model, view.shown
            return (model is not None and model.generation >= 1 and model.spec_path == str(characterized)
                    and shown is not None and shown.resyntheses >= 1)
        qtbot.waitUntil(characterized_strategy_loaded_and_a_state_shown, timeout=LOAD_WAIT)
        assert "new strategies" in view.resilience_label.text()
        assert view.shown.mode and "strategy" in view.strategy_label.text()
        view.shutdown()
    finally:
        demo.terminate()
        demo.wait(90)


@pytest.mark.timeout(1200)  # a whole scenario beside the view's own synthesis, on a busy machine
def test_controller_view_follows_ds_adoption_on_kitchen(qtbot, tmp_path, monkeypatch):
    """Live: thesis Example 13 (launch/kitchen.launch). D is blocked at the door,
    negotiates with A and puts the adopted spec in place; the view attached to D loads that spec (the
    strategy generation and spec file D reports on ~state) and goes on placing D's state in it."""
    master = shared_master()  # the view's rospy node is the process's one, on the shared master
    monkeypatch.setenv("ROS_MASTER_URI", master.uri)
    out = tmp_path / "specs"
    out.mkdir()
    adopted = out / "D.structuredslugs"
    launch = master.run(["roslaunch", "ltl_stack", "kitchen.launch", f"out:={out}"], name="gui_kitchen")
    view = None
    try:
        state = "/kitchen/D/controller_executor/state"
        master.wait_for_publisher(state, timeout=120)
        view = ControllerView()
        qtbot.addWidget(view)
        view.spec_line_edit.setText(str(CONFIG / "kitchen" / "delivery_agent.structuredslugs"))
        view.topic_combo_box.setEditText(state)
        assert view.attach()
        qtbot.waitUntil(lambda: view.model is not None and view.shown is not None, timeout=LOAD_WAIT)

        def adopted_strategy_loaded_and_a_state_of_it_shown() -> bool:
            # the view loads the new strategy, then shows the next state it is given (a tick later); until
            # D reports a state of the new strategy, the last one shown may be of the old
            model, shown = view.model, view.shown
            return (model is not None and model.generation >= 1 and model.spec_path == str(adopted)
                    and shown is not None and shown.generation >= 1 and shown.spec_file == str(adopted))
        qtbot.waitUntil(adopted_strategy_loaded_and_a_state_of_it_shown, timeout=LOAD_WAIT)
        assert view.shown.negotiations >= 1 and view.shown.negotiated >= 1  # D negotiated with A and adopted
        assert f"negotiations {view.shown.negotiations}" in view.resilience_label.text()
        assert view.strategy_label.text().startswith(f"strategy {view.model.generation}: {adopted} (")
        delivered = "kitchen_world: D delivered the ingredients to storage"

        def back_in_company_placed_in_the_adopted_strategy() -> bool:
            # D walks back from storage to the company after the delivery (kitchen_world); the view has
            # placed that state (whenever the new strategy was loaded, before or after D got there)
            if view.model is None:  # loading a newer strategy: nothing is placed meanwhile
                return False
            update, current = view.shown, view.model.current
            return (view.model.spec_path == str(adopted) and current is not None
                    and bool(update.inputs.get("company_c")) and delivered in launch.output())
        qtbot.waitUntil(back_in_company_placed_in_the_adopted_strategy, timeout=LOAD_WAIT)
        assert view.model.automaton.states[view.model.current].goal == view.shown.goal
        qtbot.waitUntil(lambda: view.current_node_id() is not None, timeout=120_000)  # drawn and highlighted
        state_now = view.model.automaton.states[view.model.current]
        assert view.state_label.text().startswith(f"state {state_now.id} ")
        assert "(road_c' | storage_c') -> openDoor_A'" in adopted.read_text()
        view.shutdown()
    except (AssertionError, QtTimeoutError) as err:  # the view's and the robots' story say where it stopped
        seen = "" if view is None else (f"view: {view.strategy_label.text()!r} {view.state_label.text()!r} "
                                        f"{view.mode_label.text()!r} {view.status_label.text()!r} last ~state {view.shown}")
        raise AssertionError(f"{err}\n{seen}\n{launch.output()[-4000:]}") from None
    finally:
        launch.stop()

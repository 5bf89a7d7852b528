"""The panels never show a wrong answer without a warning (offscreen, pytest-qt, no master).

Each test names the defect of the issue it covers; each fails on the panels as they were before."""
from __future__ import annotations

import json
import os
import threading

import pytest
from gui_data import CLEAN_MAPPING, CLEAN_SPEC, CONFIG, SIMPLE_MAPPING, SIMPLE_SPEC, simple_snapshot

pytest.importorskip("pytestqt")

from ltl_stack.analysis import cli as analysis_cli  # noqa: E402
from ltl_stack.analysis.snapshot import Snapshot  # noqa: E402
from ltl_stack.gui.analysis_panel import AnalysisPanel  # noqa: E402
from ltl_stack.gui.mapping_model import INPUT, OUTPUT  # noqa: E402
from ltl_stack.runtime.config.mapping import load_mapping  # noqa: E402

WAIT = 60_000  # ms: generous, the machine is busy
KITCHEN = CONFIG / "kitchen"

TYPO_MAPPING = """namespace: 'simple'
inputs:
  person: {node: 'person', node_publish_topic: 'person'}
outputs:
  move: {node: 'moov', node_subscribe_topic: 'move'}
  stop: {node: 'stpo', node_subscribe_topic: 'stop'}
"""


def two_publishers_snapshot() -> Snapshot:
    """Example 7's graph with a second node publishing the input topic /simple/inputs/person."""
    snap = simple_snapshot()
    snap.topics["/simple/inputs/person"].publishers = ["/simple/intruder", "/simple/person"]
    snap.nodes = sorted({*snap.nodes, "/simple/intruder"})
    return snap


def analysis_panel(qtbot, spec, mapping, snapshot_file) -> AnalysisPanel:
    panel = AnalysisPanel(take_snapshot=lambda uri: pytest.fail("no live snapshot here"))
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(spec))
    panel.mapping_line_edit.setText(str(mapping))
    panel.snapshot_line_edit.setText(str(snapshot_file))
    return panel


def analyzed(qtbot, panel: AnalysisPanel) -> AnalysisPanel:
    assert panel.analyze()
    qtbot.waitUntil(lambda: not panel.busy, timeout=WAIT)
    assert panel.result is not None, panel.status_label.text()
    return panel


def test_defect1_every_problem_analyze_graph_reports_is_listed_in_the_panel(qtbot, tmp_path, capsys):
    mapping = tmp_path / "typos.yaml"
    mapping.write_text(TYPO_MAPPING)
    snap = tmp_path / "graph.yaml"
    two_publishers_snapshot().save(snap)
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, mapping, snap))
    shown = [panel.problems_list_widget.item(i).text() for i in range(panel.problems_list_widget.count())]
    assert analysis_cli.main(["--spec", str(SIMPLE_SPEC), "--mapping", str(mapping), "--snapshot", str(snap),
                              "--json"]) == 0
    cli_problems = json.loads(capsys.readouterr().out)["problems"]
    assert cli_problems and [f"{p['severity']}: {p['text']}" for p in cli_problems] == shown
    text = "\n".join(shown)
    assert "node /simple/moov" in text and "node /simple/stpo" in text  # every misspelt output node
    assert "/simple/inputs/person is also published by /simple/intruder" in text
    # and the picture does not claim a clean result
    assert "problem(s)" in panel.status_label.text()


def test_defect1_a_clean_run_says_so(qtbot, tmp_path):
    snap = tmp_path / "graph.yaml"
    simple_snapshot().save(snap)
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    assert panel.result.problems == []
    assert panel.problems_list_widget.item(0).text().startswith("No problems")


def test_defect4_a_failed_analysis_clears_the_old_results_and_apply(qtbot, tmp_path):
    snap = tmp_path / "graph.yaml"
    simple_snapshot().save(snap)
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    assert panel.models["E2"].rowCount() == 2 and panel.apply_push_button.isEnabled()
    panel.snapshot_line_edit.setText(str(tmp_path / "absent.yaml"))
    assert panel.analyze()
    qtbot.waitUntil(lambda: not panel.busy, timeout=WAIT)
    assert panel.result is None
    assert all(m.rowCount() == 0 for m in panel.models.values())
    assert panel.suggestions_text.toPlainText() == "" and panel.problems_list_widget.count() == 0
    assert not panel.apply_push_button.isEnabled()
    assert not panel.apply()  # and nothing is written from the old tables
    assert not list(tmp_path.glob("*slugsin"))


def test_defect4_changed_inputs_grey_the_results_until_analysed_again(qtbot, tmp_path):
    snap = tmp_path / "graph.yaml"
    simple_snapshot().save(snap)
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    panel.apply_text.setPlainText("an old verdict")
    panel.robots_line_edit.setText("r1, r2")
    assert panel.stale and not panel.findings_tab_widget.isEnabled()
    assert not panel.apply_push_button.isEnabled() and panel.apply_text.toPlainText() == ""
    assert "stale" in panel.status_label.text()
    analyzed(qtbot, panel)
    assert not panel.stale and panel.findings_tab_widget.isEnabled() and panel.apply_push_button.isEnabled()


def test_defect4_the_amended_path_follows_the_current_spec_unless_typed(qtbot, tmp_path):
    snap = tmp_path / "graph.yaml"
    simple_snapshot().save(snap)
    other = tmp_path / "other.structuredslugs"
    other.write_text(SIMPLE_SPEC.read_text())
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    assert panel.amended_line_edit.text() == str(SIMPLE_SPEC.with_name("simple_with_suggestions.slugsin"))
    panel.spec_line_edit.setText(str(other))
    analyzed(qtbot, panel)
    assert panel.amended_line_edit.text() == str(tmp_path / "other_with_suggestions.slugsin")
    panel.amended_line_edit.setText(str(tmp_path / "mine.slugsin"))
    panel.spec_line_edit.setText(str(SIMPLE_SPEC))
    analyzed(qtbot, panel)
    assert panel.amended_line_edit.text() == str(tmp_path / "mine.slugsin")


# --- mapping panel --------------------------------------------------------------------------------------

@pytest.fixture
def mapping_panel(qtbot):
    from test_gui_models import clean_graph

    from ltl_stack.gui.mapping_panel import MappingPanel

    graph = clean_graph()
    panel = MappingPanel(take_graph=lambda uri: graph)
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(CLEAN_SPEC))
    panel.mapping_line_edit.setText(str(CLEAN_MAPPING))
    assert panel.load(), panel.status_label.text()
    panel.refresh()
    qtbot.waitUntil(lambda: panel.graph is not None, timeout=WAIT)
    return panel


def wheel(widget, steps: int = -1) -> None:
    from python_qt_binding.QtCore import QPoint, QPointF, Qt
    from python_qt_binding.QtGui import QWheelEvent
    from python_qt_binding.QtWidgets import QApplication

    centre = QPointF(widget.rect().center())
    event = QWheelEvent(centre, QPointF(widget.mapToGlobal(centre.toPoint())), QPoint(0, 0), QPoint(0, 120 * steps),
                        Qt.NoButton, Qt.NoModifier, Qt.NoScrollPhase, False)
    QApplication.sendEvent(widget, event)


def test_defect3_the_wheel_over_a_drop_down_without_focus_never_edits(mapping_panel, qtbot):
    panel = mapping_panel
    panel.show()
    node = panel.combo(OUTPUT, "stop", 0, "node")
    assert node.count() > 2 and node.currentText() == "stop"
    panel.spec_line_edit.setFocus()
    for _ in range(3):
        wheel(node, -1)
        wheel(node, 1)
        wheel(node, 1)
    assert node.currentText() == "stop" and panel.doc.rows[(OUTPUT, "stop")][0].node == "stop"
    assert not panel.dirty
    node.setFocus()
    qtbot.waitUntil(node.hasFocus, timeout=WAIT)
    wheel(node, -1)  # with the focus the wheel is the user's choice
    assert node.currentText() != "stop"


def test_defect5_a_master_typed_in_a_panel_never_changes_the_process_environment(qtbot, monkeypatch):
    from ltl_stack.gui.mapping_panel import MappingPanel

    monkeypatch.setenv("ROS_MASTER_URI", "http://localhost:11399/")
    panel = MappingPanel()  # the real master reader
    qtbot.addWidget(panel)
    panel.master_line_edit.setText("http://127.0.0.1:1/")  # nothing listens there
    panel.refresh()
    qtbot.waitUntil(lambda: "Refresh failed" in panel.status_label.text(), timeout=WAIT)
    assert "127.0.0.1:1" in panel.status_label.text()
    assert os.environ["ROS_MASTER_URI"] == "http://localhost:11399/"


def test_defect7_saving_a_mapping_keeps_its_negotiation_section(qtbot, tmp_path):
    from ltl_stack.gui.mapping_panel import MappingPanel

    panel = MappingPanel(take_graph=lambda uri: pytest.fail("no master here"))
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(KITCHEN / "chef.structuredslugs"))
    panel.mapping_line_edit.setText(str(KITCHEN / "chef.yaml"))
    assert panel.load(), panel.status_label.text()
    out = tmp_path / "chef.yaml"
    assert panel.save(str(out)), panel.status_label.text()
    original = load_mapping(KITCHEN / "chef.yaml")
    assert original.negotiation and load_mapping(out).negotiation == original.negotiation


def test_defect9_a_name_picked_from_the_master_stays_relative_in_a_relative_mapping(mapping_panel):
    panel = mapping_panel
    for which, absolute, short in (("node", "/clean_and_patrol/drop", "drop"),
                                   ("topic", "/clean_and_patrol/inputs/drop_ac", "drop_ac")):
        combo = panel.combo(INPUT, "pickup_ac", 0, which)
        if which == "topic":  # the node's topics are listed once the node is chosen
            combo = panel.combo(INPUT, "pickup_ac", 0, "topic")
        index = combo.findText(absolute)
        assert index >= 0, [combo.itemText(i) for i in range(combo.count())]
        combo.setCurrentIndex(index)
        combo.activated.emit(index)  # what a pick in the popup emits
        assert combo.currentText() == short
    row = panel.doc.rows[(INPUT, "pickup_ac")][0]
    assert (row.node, row.topic) == ("drop", "drop_ac")


def test_defect9_save_asks_and_generate_refuses_while_errors_are_listed(mapping_panel, qtbot, tmp_path):
    panel = mapping_panel
    panel.combo(INPUT, "object", 0, "node").setEditText("/nobody")  # a second publisher: an error
    assert panel.errors()
    asked = []
    panel.confirm = lambda title, text: asked.append(text) or False
    out = tmp_path / "m.yaml"
    assert not panel.save(str(out)) and not out.exists() and asked and "error" in asked[0]
    launch = tmp_path / "m.launch"
    panel.mapping_line_edit.setText(str(out))
    assert not panel.generate_launch(str(launch)) and not launch.exists() and not out.exists()
    panel.confirm = lambda title, text: True
    assert panel.save(str(out)) and out.exists()


def test_defect9_an_output_node_that_does_not_subscribe_its_topic_is_flagged(mapping_panel, qtbot):
    panel = mapping_panel
    panel.combo(OUTPUT, "stop", 0, "topic").setEditText("/clean_and_patrol/outputs/pickup")
    qtbot.waitUntil(lambda: any("does not subscribe" in f.message for f in panel.findings), timeout=WAIT)
    assert any(f.proposition == "stop" and "/clean_and_patrol/stop does not subscribe" in f.message
               for f in panel.findings)


def test_defect9_load_asks_before_discarding_edits_and_undo_restores(mapping_panel):
    panel = mapping_panel
    panel.combo(OUTPUT, "stop", 0, "node").setEditText("brake")
    assert panel.dirty
    panel.confirm = lambda title, text: False
    assert not panel.load()
    assert panel.doc.rows[(OUTPUT, "stop")][0].node == "brake"
    panel.undo()
    assert panel.doc.rows[(OUTPUT, "stop")][0].node == "stop"
    assert panel.combo(OUTPUT, "stop", 0, "node").currentText() == "stop"
    panel.confirm = lambda title, text: True
    assert panel.load()


def test_defect9_add_and_delete_keep_the_scroll_position(mapping_panel, qtbot):
    panel = mapping_panel
    panel.resize(900, 420)
    panel.show()
    table = panel.outputs_table_widget
    bar = table.verticalScrollBar()
    qtbot.waitUntil(lambda: bar.maximum() > 0, timeout=WAIT)
    bar.setValue(bar.maximum())
    before = bar.value()
    assert before > 0
    last = panel.doc.outputs[-1]
    panel.add_row(last)
    assert bar.value() == before
    panel.delete_row(OUTPUT, last, len(panel.doc.rows[(OUTPUT, last)]) - 1)
    assert bar.value() == before


def test_defect9_both_tables_show_ten_rows_at_1280x800(mapping_panel, qtbot):
    panel = mapping_panel
    panel.resize(1280, 720)  # 1280x800 less rqt's title, menu and dock bars
    panel.show()
    for table in (panel.inputs_table_widget, panel.outputs_table_widget):
        qtbot.waitUntil(lambda t=table: t.viewport().height() > 0, timeout=WAIT)
        assert table.viewport().height() // table.rowHeight(0) >= 10, table.objectName()


# --- controller view ------------------------------------------------------------------------------------

class RecordingLink:
    """The ROS link's interface; records the thread it was made on (a master call in the real one)."""

    made_on: list[str] = []

    def __init__(self, topic, on_state, on_diagnostic):
        RecordingLink.made_on.append(threading.current_thread().name)
        self.put = on_state

    def params(self):
        RecordingLink.made_on.append(threading.current_thread().name)
        return {}

    def set_running(self, running):
        return "ok"

    def close(self):
        pass


def test_defect6_refresh_and_attach_call_the_master_off_the_gui_thread(qtbot):
    from ltl_stack.gui.controller_view import ControllerView

    listed_on = []
    RecordingLink.made_on = []

    def list_topics():
        listed_on.append(threading.current_thread().name)
        return ["/clean_and_patrol/controller_executor/state"]
    view = ControllerView(link_factory=RecordingLink, list_topics=list_topics)
    qtbot.addWidget(view)
    assert view.refresh_topics()
    qtbot.waitUntil(lambda: view.topic_combo_box.currentText() != "", timeout=WAIT)
    view.spec_line_edit.setText(str(SIMPLE_SPEC))
    assert view.attach()
    qtbot.waitUntil(lambda: view.model is not None, timeout=WAIT)
    gui = threading.current_thread().name
    assert listed_on and gui not in listed_on
    assert len(RecordingLink.made_on) == 2 and gui not in RecordingLink.made_on
    view.shutdown()


def test_defect6_no_master_is_reported_and_rospy_never_waits_for_one(qtbot, monkeypatch):
    import rospy

    from ltl_stack.gui.controller_view import ControllerView

    if rospy.core.is_initialized():
        pytest.skip("rospy was initialized by another test in this process")
    monkeypatch.setenv("ROS_MASTER_URI", "http://127.0.0.1:1/")  # nothing listens there
    view = ControllerView()  # the real ROS link and topic listing
    qtbot.addWidget(view)
    assert view.refresh_topics()
    qtbot.waitUntil(lambda: "no ROS master answers at http://127.0.0.1:1/" in view.status_label.text(),
                    timeout=WAIT)
    view.spec_line_edit.setText(str(SIMPLE_SPEC))
    view.topic_combo_box.setEditText("/simple/controller_executor/state")
    assert view.attach()
    qtbot.waitUntil(lambda: "Cannot attach: no ROS master" in view.status_label.text(), timeout=WAIT)
    assert view.attach_push_button.isEnabled() and view.refresh_push_button.isEnabled()
    assert not rospy.core.is_initialized()


def test_item11_an_unrealizable_spec_is_one_line_in_the_view_not_a_traceback(qtbot, tmp_path, capfd):
    from ltl_stack.gui.controller_view import ControllerView

    spec = tmp_path / "never.structuredslugs"
    spec.write_text("[INPUT]\nx\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n!y'\n\n[SYS_LIVENESS]\ny\n")
    view = ControllerView(link_factory=RecordingLink)
    qtbot.addWidget(view)
    view.spec_line_edit.setText(str(spec))
    view.topic_combo_box.setEditText("/never/controller_executor/state")
    assert view.attach()
    qtbot.waitUntil(lambda: "the specification is unrealizable" in view.status_label.text(), timeout=WAIT)
    view.task.thread.join(WAIT / 1000)
    assert "Traceback" not in capfd.readouterr().err


def test_cancel_stops_attaching_and_lets_the_topic_go(qtbot, capfd):
    """Cancel while the view attaches: the synthesis stops at its next step (it is not run to the end for
    nothing), the link is closed, nothing is shown, no traceback."""
    from ltl_stack.gui.controller_view import ControllerView

    asked, go, closed = threading.Event(), threading.Event(), []

    class SlowLink(RecordingLink):
        def params(self):
            asked.set()
            go.wait(60)  # the master answers slowly
            return {}

        def close(self):
            closed.append(threading.current_thread().name)
    view = ControllerView(link_factory=SlowLink)
    qtbot.addWidget(view)
    view.spec_line_edit.setText(str(SIMPLE_SPEC))
    view.topic_combo_box.setEditText("/simple/controller_executor/state")
    assert view.attach() and not view.cancel_push_button.isHidden()
    assert asked.wait(60)
    assert view.cancel() and view.cancel_push_button.isHidden() and view.attach_push_button.isEnabled()
    assert "Cancelled" in view.status_label.text()
    go.set()
    view.task.thread.join(60)
    assert not view.task.thread.is_alive()
    qtbot.wait(100)
    assert closed and view.model is None and view.link is None and "Cancelled" in view.status_label.text()
    assert "Traceback" not in capfd.readouterr().err


def test_the_view_synthesizes_in_a_process_of_its_own(qtbot, monkeypatch):
    """A synthesis' CUDD calls hold the GIL (the GUI stalled ~400 ms attaching spheros): the view
    synthesizes in its worker process, started once, ended with the view."""
    from ltl_stack.gui import controller_view

    monkeypatch.setattr(controller_view.ControllerModel, "synthesize",
                        classmethod(lambda *a, **k: pytest.fail("synthesized in the GUI's process")))
    view = attached_view(qtbot, SIMPLE_SPEC)
    child = view.worker._proc
    assert child is not None and child.pid != os.getpid() and child.poll() is None
    assert len(view.model.automaton) > 1 and view.model.predecessors(0) is not None
    view.close()
    assert child.wait(60) is not None


def test_killing_the_worker_process_stops_a_running_synthesis_at_once():
    """Cancel kills the worker process: a long synthesis (spheros, 65,536 states) ends at once with one
    line, and the next job starts a new process."""
    from ltl_stack.gui.controller_model import ViewOptions
    from ltl_stack.gui.worker_process import WorkerProcess, WorkFailed, controller_model

    worker, started, failed = WorkerProcess(), threading.Event(), []

    def attach():
        try:
            controller_model(worker, str(CONFIG / "spheros" / "spheros.slugsin"), ViewOptions(),
                             lambda _text: started.set())
        except WorkFailed as err:
            failed.append(str(err))
    thread = threading.Thread(target=attach)
    thread.start()
    assert started.wait(60)  # the child reports that it synthesizes
    child = worker._proc
    worker.kill()
    thread.join(60)
    assert not thread.is_alive() and child.poll() is not None
    assert failed == ["the worker process ended unexpectedly"]
    model = controller_model(worker, str(SIMPLE_SPEC), ViewOptions(), lambda _text: None)
    assert worker._proc is not child and len(model.automaton) > 1
    worker.close()


def test_a_cancelled_task_stops_at_its_next_progress_and_hands_a_late_result_to_discard(qtbot):
    from ltl_stack.gui.widgets import Cancelled, Task

    go, reports, ended = threading.Event(), [], []

    def endless(progress):
        try:
            while True:
                progress("step")
                reports.append(1)
                go.wait(0.01)
        except Cancelled:
            ended.append("cancelled")
            raise
    task = Task(endless)
    task.start()
    qtbot.waitUntil(lambda: len(reports) > 3, timeout=WAIT)
    task.abandon()
    task.thread.join(60)
    assert ended == ["cancelled"] and not task.thread.is_alive()

    discarded, finished = [], []
    late = Task(lambda _progress: "a link to close", discard=discarded.append)
    late.finished.connect(finished.append)
    late.start()
    late.thread.join(60)  # done, its delivery still queued for the GUI thread
    late.abandon()
    qtbot.waitUntil(lambda: discarded == ["a link to close"], timeout=WAIT)
    assert finished == []


def attached_view(qtbot, spec, full_limit: int | None = None, radius: int | None = None):
    """A view attached to ``spec`` through ``RecordingLink``, its first picture drawn (whole graph up to
    ``full_limit`` states, else a neighbourhood of ``radius``, when given)."""
    from ltl_stack.gui.controller_view import ControllerView

    view = ControllerView(link_factory=RecordingLink)
    qtbot.addWidget(view)
    view.spec_line_edit.setText(str(spec))
    view.topic_combo_box.setEditText("/x/controller_executor/state")
    if full_limit is not None:
        view.full_spin_box.setValue(full_limit)
    if radius is not None:
        view.radius_spin_box.setValue(radius)
    assert view.attach()
    qtbot.waitUntil(lambda: view.model is not None and view.graph_view.graph is not None, timeout=WAIT)
    return view


def test_defect2_the_view_shows_the_resilience_mode_counters_and_violated_clauses(qtbot):
    from ltl_stack.gui.controller_model import MODES, StateUpdate

    view = attached_view(qtbot, SIMPLE_SPEC)
    s = view.model.automaton.states[view.model.automaton.initial[0]]
    clause = "simple.structuredslugs:12: if you are sensing person then do stop"
    view.latest.put(StateUpdate(s.id, s.goal, s.inputs, s.outputs, True, mode="recovering", violations=181,
                                recovery_steps=7, resyntheses=0, violated_clauses=(clause,)))
    qtbot.waitUntil(lambda: "recovering" in view.mode_label.text(), timeout=WAIT)
    assert MODES["recovering"][1] in view.mode_label.styleSheet()
    assert "violations 181" in view.resilience_label.text() and "recovery steps 7" in view.resilience_label.text()
    assert view.violated_list_widget.item(0).text() == clause
    view.latest.put(StateUpdate(s.id, s.goal, s.inputs, s.outputs, True, mode="normal", violations=181))
    qtbot.waitUntil(lambda: view.violated_list_widget.count() == 0, timeout=WAIT)
    assert MODES["normal"][1] in view.mode_label.styleSheet()
    view.shutdown()


def test_defect2_after_a_resynthesis_the_view_loads_the_new_strategy(qtbot, tmp_path):
    from ltl_stack.gui.controller_model import StateUpdate

    view = attached_view(qtbot, SIMPLE_SPEC)
    old = view.model
    characterized = tmp_path / "simple_characterized.structuredslugs"  # as --characterized-spec writes it
    characterized.write_text(SIMPLE_SPEC.read_text() + "\n[ENV_TRANS]\n!person'\n")
    s = old.automaton.states[old.automaton.initial[0]]
    view.latest.put(StateUpdate(s.id, s.goal, s.inputs, s.outputs, True, mode="normal", resyntheses=1,
                                spec_file=str(characterized), generation=1))
    qtbot.waitUntil(lambda: view.model is not old and view.model.generation == 1, timeout=WAIT)
    assert view.model.spec_path == str(characterized)
    new = view.model.automaton.states[view.model.automaton.initial[0]]
    view.latest.put(StateUpdate(new.id, new.goal, new.inputs, new.outputs, True, spec_file=str(characterized),
                                generation=1))
    qtbot.waitUntil(lambda: view.model.current == new.id and view.current_node_id() is not None, timeout=WAIT)
    assert "strategy 1" in view.strategy_label.text()
    view.shutdown()


def test_defect2_a_new_strategy_without_a_file_is_said_not_hidden(qtbot):
    from ltl_stack.gui.controller_model import StateUpdate

    view = attached_view(qtbot, SIMPLE_SPEC)
    s = view.model.automaton.states[view.model.automaton.initial[0]]
    view.latest.put(StateUpdate(s.id, s.goal, s.inputs, s.outputs, True, resyntheses=1, generation=1))
    qtbot.waitUntil(lambda: "not written to a file" in view.strategy_label.text(), timeout=WAIT)
    view.shutdown()


# --- pictures that scale (defect 8) ------------------------------------------------------------------------

ALICE_SPEC = CONFIG / "alice" / "alice.structuredslugs"  # 30 states, 8 initial, 232 edges


def test_defect8_the_layout_never_gets_more_than_a_bounded_neighbourhood():
    from ltl_stack.gui.controller_model import MAX_DRAWN_EDGES, ControllerModel, ViewOptions

    model = ControllerModel.synthesize(str(ALICE_SPEC))
    assert len(model.automaton) <= model.options.full_limit and not model.whole  # few states, too many edges
    for center in (None, *range(len(model.automaton))):
        g = model.graph(center)
        assert len(g.edges) <= MAX_DRAWN_EDGES and len(g.nodes) <= model.options.full_limit
    small = ControllerModel(model.spec_path, model.automaton, ViewOptions(full_limit=3, radius=1))
    assert len(model.automaton.initial) > 3 and len(small.graph(None).nodes) <= 3  # not every initial state


def test_defect8_a_neighbourhood_seen_before_is_drawn_from_the_cache(qtbot):
    from ltl_stack.gui.controller_model import StateUpdate

    view = attached_view(qtbot, ALICE_SPEC, full_limit=4, radius=1)
    a = view.model.automaton
    first = a.initial[0]
    far = next(s.id for s in a.states if s.id not in view.model.shown_states(first))
    for sid in (first, far, first, far, first):
        s = a.states[sid]
        view.latest.put(StateUpdate(sid, s.goal, s.inputs, s.outputs, True))
        qtbot.waitUntil(lambda sid=sid: view.model.current == sid and view.current_node_id() is not None,
                        timeout=WAIT)
    assert view.layout_count <= 3  # the start, first's and far's neighbourhoods: each laid out once
    view.shutdown()


def test_defect8_a_state_that_leaves_the_picture_is_highlighted_before_graphviz_answers(qtbot, monkeypatch):
    """Highlight within one frame of the label: a state outside the drawn neighbourhood is drawn at once
    in a sketch of its neighbourhood (Graphviz held back here), then in Graphviz's layout when it comes."""
    from ltl_stack.gui import widgets
    from ltl_stack.gui.controller_model import StateUpdate

    view = attached_view(qtbot, ALICE_SPEC, full_limit=4, radius=1)
    a = view.model.automaton
    far = next(s.id for s in a.states if s.id not in view._drawn)
    release, asked = threading.Event(), []
    real = widgets.GraphView.layout_for

    def held(self, graph):
        asked.append(graph)
        release.wait(WAIT / 1000)
        return real(self, graph)
    monkeypatch.setattr(widgets.GraphView, "layout_for", held)
    try:
        s = a.states[far]
        view.latest.put(StateUpdate(far, s.goal, s.inputs, s.outputs, True))
        qtbot.waitUntil(lambda: view.model.current == far, timeout=WAIT)
        assert view.current_node_id() is not None and view.graph_view._marks  # in the frame of the label
        assert view.sketch_count == 1
        qtbot.waitUntil(lambda: len(asked) == 1, timeout=WAIT)  # Graphviz is asked for the same neighbourhood
        assert set(asked[0].key) == set(view.graph_view.graph.key)
    finally:
        release.set()
    qtbot.waitUntil(lambda: not view.layout_task.running, timeout=WAIT)
    qtbot.waitUntil(lambda: (id(view.model), far) in view._layouts, timeout=WAIT)
    assert view.graph_view.graph is view._layouts[(id(view.model), far)][0] and view.current_node_id() is not None
    view.shutdown()

def test_defect8_every_graph_saves_as_png_svg_and_dot(qtbot, tmp_path):
    from python_qt_binding.QtGui import QImage

    from ltl_stack.gui.controller_model import ControllerModel
    from ltl_stack.gui.widgets import GraphView

    view = GraphView()
    qtbot.addWidget(view)
    graph = ControllerModel.synthesize(str(SIMPLE_SPEC)).graph()
    view.draw(graph)
    for ext in ("png", "svg", "dot"):
        view.save(str(tmp_path / f"g.{ext}"))
    assert not QImage(str(tmp_path / "g.png")).isNull()
    assert "<svg" in (tmp_path / "g.svg").read_text() and (tmp_path / "g.dot").read_text() == graph.to_dot()
    with pytest.raises(ValueError):
        view.save(str(tmp_path / "g.gif"))


# --- smaller items (11) -----------------------------------------------------------------------------------

class DictSettings(dict):
    def set_value(self, key, value):
        self[key] = value

    def value(self, key, default=None):
        return self.get(key, default)


def test_item11_a_restored_perspective_attaches_the_controller_view_again(qtbot):
    from ltl_stack.gui.controller_view import ControllerView

    settings = DictSettings()
    first = ControllerView(link_factory=RecordingLink)
    qtbot.addWidget(first)
    first.spec_line_edit.setText(str(SIMPLE_SPEC))
    first.topic_combo_box.setEditText("/simple/controller_executor/state")
    first.save_settings(settings)
    view = ControllerView(link_factory=RecordingLink)
    qtbot.addWidget(view)
    view.restore_settings(settings)
    qtbot.waitUntil(lambda: view.model is not None and view.link is not None, timeout=WAIT)
    assert view.model.spec_path == str(SIMPLE_SPEC)
    view.shutdown()


@pytest.mark.parametrize("name", ["mapping_panel", "analysis_panel", "controller_view"])
def test_item11_standalone_windows_fit_a_1280x800_screen(qtbot, name):
    from ltl_stack.gui.standalone import make_panel, window_size

    panel = make_panel(name)
    qtbot.addWidget(panel)
    width, height = window_size(1280, 800)
    assert width <= 1280 and height <= 800 - 40  # room for the title bar
    hint = panel.minimumSizeHint()
    assert hint.width() <= width and hint.height() <= height, (hint.width(), hint.height())
    if hasattr(panel, "shutdown"):
        panel.shutdown()


def test_item11_the_check_tabs_say_what_they_check(qtbot):
    panel = AnalysisPanel(take_snapshot=lambda uri: pytest.fail("no live snapshot here"))
    qtbot.addWidget(panel)
    tips = [panel.findings_tab_widget.tabToolTip(i) for i in range(panel.findings_tab_widget.count())]
    assert all(tips) and "same topic or action" in tips[1] and "thesis 3.5.2" in tips[0]


def test_defect8_long_labels_graphviz_continues_on_a_new_line_are_laid_out(qtbot):
    """spheros' states list ten outputs and "+32795 edges": Graphviz's -Tplain continues such lines
    with a backslash-newline, which the plain renderer's parser failed on (no picture at all)."""
    from ltl_stack.gui.dotgraph import DotGraph, layout_plain

    g = DotGraph()
    outs = ", ".join(f"turn_colour_{k}" for k in range(10))
    for i in range(3):
        g.add_node(i, f"{32767 + i} (goal 0)\n{outs}\n(+32795 edges)", shape="box")
    g.add_edge(0, 1, "a")
    g.add_edge(1, 2, "b")
    laid_out = layout_plain(g.to_dot())
    assert set(laid_out.nodes) == {"n0", "n1", "n2"} and len(laid_out.edges) == 2
    assert laid_out.nodes["n1"].label.endswith("(+32795 edges)")


def test_defect8_the_analysis_panel_lays_findings_out_off_the_gui_thread_once_each(qtbot, tmp_path, monkeypatch):
    from ltl_stack.gui import widgets

    snap = tmp_path / "graph.yaml"
    simple_snapshot().save(snap)
    threads = []
    real = widgets.layout_plain

    def recording(text, *args, **kwargs):
        threads.append(threading.current_thread().name)
        return real(text, *args, **kwargs)
    monkeypatch.setattr(widgets, "layout_plain", recording)
    monkeypatch.setattr(widgets.GraphView, "layout_for", lambda self, graph: recording(graph.to_dot()))
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    qtbot.waitUntil(lambda: panel.graph_view.graph is not None, timeout=WAIT)
    for _ in range(3):  # clicking the finding again draws it from the cache
        panel.views["E2"].clearSelection()
        panel.select_finding("E2", 0)
    assert len(threads) == 1 and threads[0] != threading.current_thread().name



def test_the_analysis_runs_with_the_garbage_collector_paused(qtbot):
    """A full collection on the analysis' worker holds the GIL and stalls the GUI thread (90-500 ms on the
    10,000-node graph, bench_gui --pictures): the collector is paused while the analysis runs, then on."""
    import gc

    seen = []

    def snapshot(_uri):
        seen.append(gc.isenabled())
        return simple_snapshot()
    panel = AnalysisPanel(take_snapshot=snapshot)
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SIMPLE_SPEC))
    panel.mapping_line_edit.setText(str(SIMPLE_MAPPING))
    panel.live_check_box.setChecked(True)
    assert gc.isenabled()
    analyzed(qtbot, panel)
    assert seen == [False] and gc.isenabled()


def test_the_gil_changes_hands_quickly_while_any_task_runs(qtbot):
    """Every event PyQt hands to Python waits for the GIL; with the default 5 ms switch interval a worker
    running Python stalled the GUI thread 300 ms per analysis (bench_gui --pictures). While tasks run the
    interval is 0.2 ms; it is set back when the last one ends, also when a task fails."""
    import sys

    from ltl_stack.gui import widgets
    from ltl_stack.gui.widgets import HANDOVER_INTERVAL_S, Task

    qtbot.waitUntil(lambda: widgets._handover["running"] == 0, timeout=WAIT)  # earlier tests' tasks ended
    before = sys.getswitchinterval()
    assert before > HANDOVER_INTERVAL_S
    go = [threading.Event(), threading.Event()]
    seen: list[float] = []

    def work(k):
        def run(_progress):
            seen.append(sys.getswitchinterval())
            go[k].wait(60)
            if k == 1:
                raise OSError("the second task fails")
            return k
        return run
    tasks = [Task(work(0)), Task(work(1))]
    for task in tasks:
        task.start()
    qtbot.waitUntil(lambda: len(seen) == 2, timeout=WAIT)
    assert seen == [pytest.approx(HANDOVER_INTERVAL_S)] * 2  # the interpreter keeps microseconds
    go[0].set()
    tasks[0].thread.join(60)
    assert sys.getswitchinterval() == pytest.approx(HANDOVER_INTERVAL_S)  # the second task still runs
    go[1].set()
    tasks[1].thread.join(60)
    assert sys.getswitchinterval() == before


def test_the_analysis_runs_in_a_process_of_its_own_and_ends_with_the_panel(qtbot, tmp_path, monkeypatch):
    """A worker thread running the analysis shares the GIL with the GUI thread (61 ms stalls on a loaded
    machine, bench_gui --pictures): the analysis runs in a child process, reused, ended with the panel."""
    from ltl_stack.gui import worker_process

    monkeypatch.setattr(worker_process, "run_analysis", lambda *a, **k: pytest.fail("analysed in the GUI's process"))
    snap = tmp_path / "graph.json"
    simple_snapshot().save(snap)
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    assert panel.result.counts()["E2"] == 1 and panel.tables["E2"].rows
    child = panel.analysis_process._proc
    assert child is not None and child.pid != os.getpid() and child.poll() is None
    analyzed(qtbot, panel)
    assert panel.analysis_process._proc is child  # started once
    panel.close()
    assert child.wait(60) is not None


def test_without_its_process_the_panel_analyses_on_a_worker_thread(qtbot, tmp_path):
    snap = tmp_path / "graph.json"
    simple_snapshot().save(snap)
    panel = analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap)
    panel.analysis_process = None
    analyzed(qtbot, panel)
    assert panel.result.counts()["E2"] == 1 and panel.tables["E2"].rows


def test_cancel_stops_the_analysis_process_and_the_next_analysis_starts_another(qtbot, tmp_path):
    snap = tmp_path / "graph.json"
    simple_snapshot().save(snap)
    panel = analyzed(qtbot, analysis_panel(qtbot, SIMPLE_SPEC, SIMPLE_MAPPING, snap))
    child = panel.analysis_process._proc
    assert panel.analyze() and panel.cancel()  # nothing delivered yet: the GUI thread has not run since
    assert child.wait(60) is not None and not panel.busy
    panel.task.thread.join(60)
    qtbot.wait(100)
    assert panel.result is None and "Cancelled" in panel.status_label.text()
    analyzed(qtbot, panel)
    assert panel.analysis_process._proc is not child and panel.result.counts()["E2"] == 1


def test_cancel_drops_a_running_analysis(qtbot, tmp_path):
    release = threading.Event()

    def slow_snapshot(uri):
        release.wait(60)
        return simple_snapshot()
    panel = AnalysisPanel(take_snapshot=slow_snapshot)
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SIMPLE_SPEC))
    panel.mapping_line_edit.setText(str(SIMPLE_MAPPING))
    panel.live_check_box.setChecked(True)
    assert panel.analyze() and panel.busy and not panel.cancel_push_button.isHidden()
    assert panel.cancel()
    assert not panel.busy and panel.analyze_push_button.isEnabled() and panel.cancel_push_button.isHidden()
    task = panel.task
    release.set()
    task.thread.join(60)
    qtbot.wait(200)  # the dropped outcome would arrive now
    assert panel.result is None and "Cancelled" in panel.status_label.text()


def test_defect9_a_new_output_row_names_its_topic_relative_in_a_relative_mapping(mapping_panel):
    panel = mapping_panel
    panel.add_row("stop")
    assert panel.doc.rows[(OUTPUT, "stop")][-1].topic == "stop"  # /clean_and_patrol/outputs/stop


def test_closing_the_mapping_panel_with_unsaved_edits_asks(mapping_panel):
    panel = mapping_panel
    panel.ask_on_close = True  # as the standalone host sets it
    panel.show()
    panel.combo(OUTPUT, "stop", 0, "node").setEditText("brake")
    panel.confirm = lambda title, text: False
    assert not panel.close() and panel.isVisible()
    panel.confirm = lambda title, text: True
    assert panel.close()


@pytest.mark.parametrize("pair", [("mapping_panel", "controller_view"), ("analysis_panel", "controller_view"),
                                  ("mapping_panel", "analysis_panel")])
def test_two_panels_docked_side_by_side_fit_a_1280_px_screen(qtbot, pair):
    """Two panels docked side by side fit a 1280 px screen (they made rqt's window 1353-1510 px wide).
    Docked as rqt docks
    plugins (a QDockWidget each in a QMainWindow), the window opens and can be made at most 1280 px wide."""
    from python_qt_binding.QtCore import Qt
    from python_qt_binding.QtWidgets import QDockWidget, QMainWindow

    from ltl_stack.gui.standalone import make_panel

    window = QMainWindow()
    qtbot.addWidget(window)
    panels = []
    for name, area in ((pair[0], Qt.LeftDockWidgetArea), (pair[1], Qt.RightDockWidgetArea)):
        panel = make_panel(name)
        dock = QDockWidget(name, window)
        dock.setWidget(panel)
        window.addDockWidget(area, dock)
        panels.append(panel)
    window.show()
    qtbot.waitExposed(window)
    assert window.minimumSizeHint().width() <= 1280, window.minimumSizeHint()
    assert window.sizeHint().width() <= 1280 and window.width() <= 1280, (window.sizeHint(), window.width())
    for panel in panels:
        if hasattr(panel, "shutdown"):
            panel.shutdown()

"""The three panels as widgets, offscreen with pytest-qt, without a master: the graph comes from a
snapshot, the executor from a test double of the ROS link (the live tests use the real ones)."""
from __future__ import annotations

import subprocess
import sys

import pytest
from gui_data import CLEAN_MAPPING, CLEAN_SPEC, ROOT, SIMPLE_MAPPING, SIMPLE_SPEC, simple_snapshot
from test_gui_models import clean_graph

from ltl_stack.runtime.config.mapping import load_mapping

pytest.importorskip("pytestqt")
from python_qt_binding.QtWidgets import QComboBox, QPushButton  # noqa: E402

from ltl_stack.gui.analysis_panel import AnalysisPanel  # noqa: E402
from ltl_stack.gui.controller_model import StateUpdate  # noqa: E402
from ltl_stack.gui.controller_view import ControllerView  # noqa: E402
from ltl_stack.gui.mapping_model import INPUT, OUTPUT  # noqa: E402
from ltl_stack.gui.mapping_panel import MappingPanel  # noqa: E402
from ltl_stack.gui.widgets import GraphView  # noqa: E402

WAIT = 60_000  # ms: generous, the machine is busy


class DictSettings:
    """rqt's Settings interface over a dict."""

    def __init__(self):
        self.data = {}

    def set_value(self, key, value):
        self.data[key] = value

    def value(self, key, default=None):
        return self.data.get(key, default)


# --- mapping panel ------------------------------------------------------------------------------------

@pytest.fixture
def mapping_panel(qtbot):
    graph = clean_graph()
    panel = MappingPanel(take_graph=lambda uri: graph)
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(CLEAN_SPEC))
    panel.mapping_line_edit.setText(str(CLEAN_MAPPING))
    panel.load_push_button.click()
    assert panel.doc is not None, panel.status_label.text()
    return panel


def test_mapping_panel_lists_propositions_and_fills_drop_downs_after_refresh(mapping_panel, qtbot):
    panel = mapping_panel
    assert panel.inputs_table_widget.rowCount() == len(panel.doc.inputs)
    assert panel.combo(INPUT, "object", 0, "node").currentText() == "object"
    assert panel.combo(INPUT, "object", 0, "node").count() == 0  # nothing known before a refresh
    panel.refresh_push_button.click()
    qtbot.waitUntil(lambda: panel.graph is not None, timeout=WAIT)
    node = panel.combo(INPUT, "object", 0, "node")
    assert [node.itemText(i) for i in range(node.count())] == panel.graph.nodes
    topic = panel.combo(INPUT, "pickup_ac", 0, "topic")
    assert [topic.itemText(i) for i in range(topic.count())] == ["/clean_and_patrol/inputs/pickup_ac"]
    assert panel.findings_list_widget.item(0).text() == "No problems found."


def test_mapping_panel_validates_as_the_user_edits(mapping_panel, qtbot):
    panel = mapping_panel
    panel.refresh_push_button.click()
    qtbot.waitUntil(lambda: panel.graph is not None, timeout=WAIT)
    node = panel.combo(INPUT, "object", 0, "node")
    node.setEditText("/nobody")
    qtbot.waitUntil(lambda: any("/nobody is not on the master" in f.message for f in panel.findings), timeout=WAIT)
    # the row is marked with its worst finding: /nobody would be a second publisher of the object topic
    assert "#ffc8c8" in node.styleSheet() and "other publishers" in node.toolTip()
    topic = panel.combo(INPUT, "object", 0, "topic")
    topic.setEditText("/clean_and_patrol/cmd_vel")
    qtbot.waitUntil(lambda: any("has type geometry_msgs/Twist" in f.message for f in panel.findings), timeout=WAIT)
    assert any(f.severity == "error" and "other publishers" in f.message for f in panel.findings)


def test_mapping_panel_add_delete_save_and_reload_round_trip(mapping_panel, qtbot, tmp_path):
    panel = mapping_panel
    panel.findChild(QPushButton, "stop_add_push_button").click()
    assert len(panel.doc.rows[(OUTPUT, "stop")]) == 2
    panel.combo(OUTPUT, "stop", 1, "node").setEditText("/brake")
    panel.findChild(QPushButton, "output_sawObject_0_delete_push_button").click()
    assert panel.doc.rows[(OUTPUT, "sawObject")] == []
    qtbot.waitUntil(lambda: any("'sawObject' is not mapped" in f.message for f in panel.findings), timeout=WAIT)
    out = tmp_path / "saved.yaml"
    panel.mapping_line_edit.setText(str(out))
    panel.save_push_button.click()
    saved = load_mapping(out)
    assert [e.node for e in saved.outputs["stop"]] == ["stop", "/brake"] and "sawObject" not in saved.outputs
    original = load_mapping(CLEAN_MAPPING)
    for prop in ("object", "topLane_rc"):
        a, b = saved.inputs[prop][0], original.inputs[prop][0]
        assert (a.pkg, a.filename, a.parameters) == (b.pkg, b.filename, b.parameters)
    panel.load_push_button.click()
    assert panel.combo(OUTPUT, "stop", 1, "node").currentText() == "/brake"
    launch = tmp_path / "saved.launch"
    panel.launch_line_edit.setText(str(launch))
    panel.generate_push_button.click()
    assert launch.is_file() and 'name="object"' in launch.read_text(), panel.status_label.text()


def test_mapping_panel_shows_a_bad_spec_as_one_line(qtbot, tmp_path):
    bad = tmp_path / "bad.structuredslugs"
    bad.write_text("[INPUT]\nx\n[SYS_TRANS]\nx' & & y\n")
    panel = MappingPanel(take_graph=lambda uri: None)
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(bad))
    panel.load_push_button.click()
    assert panel.doc is None and str(bad) in panel.status_label.text()
    assert "Traceback" not in panel.status_label.text()


def test_settings_round_trip_every_control(qtbot):
    first = MappingPanel(take_graph=lambda uri: None)
    qtbot.addWidget(first)
    first.spec_line_edit.setText(str(CLEAN_SPEC))
    first.mapping_line_edit.setText("/x/y.yaml")
    first.master_line_edit.setText("http://127.0.0.1:1/")
    settings = DictSettings()
    first.save_settings(settings)
    second = MappingPanel(take_graph=lambda uri: None)
    qtbot.addWidget(second)
    second.restore_settings(settings)
    assert (second.spec_line_edit.text(), second.mapping_line_edit.text(), second.master_line_edit.text()) == (
        str(CLEAN_SPEC), "/x/y.yaml", "http://127.0.0.1:1/")
    view = ControllerView(link_factory=FakeLink)
    qtbot.addWidget(view)
    view.full_spin_box.setValue(77)
    view.cooperative_check_box.setChecked(False)
    view.topic_combo_box.setEditText("/a/controller_executor/state")
    s = DictSettings()
    view.save_settings(s)
    other = ControllerView(link_factory=FakeLink)
    qtbot.addWidget(other)
    other.restore_settings(s)
    assert (other.full_spin_box.value(), other.cooperative_check_box.isChecked(),
            other.topic_combo_box.currentText()) == (77, False, "/a/controller_executor/state")
    assert not any(k.endswith("combo_box") and k.startswith(("input_", "output_")) for k in settings.data)


# --- analysis panel ---------------------------------------------------------------------------------------

def test_analysis_panel_on_a_snapshot_file_then_apply_and_check(qtbot, tmp_path):
    snap = tmp_path / "simple_graph.yaml"
    simple_snapshot().save(snap)
    panel = AnalysisPanel(take_snapshot=lambda uri: pytest.fail("no live snapshot here"))
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SIMPLE_SPEC))
    panel.mapping_line_edit.setText(str(SIMPLE_MAPPING))
    panel.snapshot_line_edit.setText(str(snap))
    panel.analyze_push_button.click()
    qtbot.waitUntil(lambda: panel.result is not None, timeout=WAIT)
    e2 = panel.models["E2"]
    assert [e2.rows[i][1] for i in range(e2.rowCount())] == ["move", "stop"]
    assert panel.findings_tab_widget.tabText(1) == "E2 (1)"
    assert panel.selected_rows("E2") == [0, 1]  # the first finding is selected, with its topic's rows
    qtbot.waitUntil(lambda: panel.graph_view.graph is not None, timeout=WAIT)  # laid out off the GUI thread
    assert {n.label for n in panel.graph_view.graph.nodes} == {"/simple/move", "/simple/cmd_vel", "/simple/stop"}
    assert len(panel.graph_view.items) == 3
    assert "mutually exclusive" in panel.suggestions_text.toPlainText()
    # the formula under each suggestion is text to read ('always ((move and not stop) or …'), which the
    # Structured English reader does not take: the drop-down must not call it Structured English
    assert panel.form_combo_box.itemText(0) == "Formula in words"
    panel.form_combo_box.setCurrentIndex(1)
    assert "G((move & !stop)" in panel.suggestions_text.toPlainText()
    panel.form_combo_box.setCurrentIndex(2)
    assert "[SYS_TRANS]" in panel.suggestions_text.toPlainText()
    panel.amended_line_edit.setText(str(tmp_path / "amended.slugsin"))
    panel.apply_push_button.click()
    qtbot.waitUntil(lambda: panel.applied is not None, timeout=WAIT)
    assert panel.verdict_label.text().startswith("UNREALIZABLE")
    text = panel.apply_text.toPlainText()
    assert "simple.structuredslugs" in text and "move'" in text


def test_selecting_one_row_of_a_topic_selects_all_its_rows(qtbot, tmp_path):
    snap = tmp_path / "g.json"
    simple_snapshot().save(snap)
    panel = AnalysisPanel()
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SIMPLE_SPEC))
    panel.mapping_line_edit.setText(str(SIMPLE_MAPPING))
    panel.snapshot_line_edit.setText(str(snap))
    panel.analyze()
    qtbot.waitUntil(lambda: panel.result is not None, timeout=WAIT)
    view = panel.views["E2"]
    view.clearSelection()
    assert panel.selected_rows("E2") == []
    view.selectRow(1)
    assert panel.selected_rows("E2") == [0, 1]


def test_analysis_errors_are_shown_not_raised(qtbot, tmp_path):
    panel = AnalysisPanel()
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SIMPLE_SPEC))
    panel.mapping_line_edit.setText(str(SIMPLE_MAPPING))
    panel.snapshot_line_edit.setText(str(tmp_path / "missing.yaml"))
    panel.analyze()
    qtbot.waitUntil(lambda: not panel.busy, timeout=WAIT)  # (a progress line names the file too)
    assert "missing.yaml" in panel.status_label.text() and panel.status_label.text() != "loading " + str(
        tmp_path / "missing.yaml")
    assert panel.result is None and panel.analyze_push_button.isEnabled()


# --- controller view --------------------------------------------------------------------------------------

class FakeLink:
    """The ROS link's interface; the test pushes states through ``put``."""

    last = None

    def __init__(self, topic, on_state, on_diagnostic):
        self.topic, self.put, self.on_diagnostic = topic, on_state, on_diagnostic
        self.running_calls = []
        FakeLink.last = self

    def params(self):
        return {"cooperative": True}

    def set_running(self, running):
        self.running_calls.append(running)
        return "ok"

    def close(self):
        pass


def test_controller_view_follows_states_and_pauses(qtbot):
    view = ControllerView(link_factory=FakeLink)
    qtbot.addWidget(view)
    view.spec_line_edit.setText(str(CLEAN_SPEC))
    view.topic_combo_box.setEditText("/clean_and_patrol/controller_executor/state")
    assert view.attach()
    qtbot.waitUntil(lambda: view.model is not None and view.graph_view.graph is not None, timeout=WAIT)
    link = FakeLink.last  # made off the GUI thread, by the attach task
    assert view.link is link
    a = view.model.automaton
    path = [a.initial[0]]
    for _ in range(4):
        path.append(a.states[path[-1]].successors[0])
    for sid in path:
        s = a.states[sid]
        link.put(StateUpdate(sid + 1000, s.goal, s.inputs, s.outputs, True))
        qtbot.waitUntil(lambda sid=sid: view.model.current == sid and view.current_node_id() is not None,
                        timeout=WAIT)
        assert view.state_label.text() == f"state {sid} (goal {s.goal + 1}/{view.model.automaton.goals})"
        lit = view.lamp_values()
        assert all(lit[n] == s.outputs[n] for n in a.outputs) and all(lit[n] == s.inputs[n] for n in a.inputs)
    assert view.graph_view._marks, "the current state is not highlighted"
    view.run_pause_push_button.click()
    qtbot.waitUntil(lambda: link.running_calls == [False], timeout=WAIT)
    s = a.states[path[-1]]
    link.put(StateUpdate(1, s.goal, s.inputs, {n: False for n in a.outputs}, False))
    qtbot.waitUntil(lambda: view.run_pause_push_button.text() == "Run", timeout=WAIT)
    assert "paused" in view.mode_label.text() or "not in the automaton" in view.state_label.text()
    link.on_diagnostic(2, "environment assumption violated by inputs ...")
    qtbot.waitUntil(lambda: "violated" in view.mode_label.text(), timeout=WAIT)
    view.shutdown()


# --- graph view and hosts ----------------------------------------------------------------------------------

def test_own_renderer_draws_when_qt_dotgraph_is_absent(qtbot):
    from ltl_stack.gui.dotgraph import DotGraph

    view = GraphView()
    qtbot.addWidget(view)
    view.renderer = "plain"
    g = DotGraph()
    g.add_node("a", "a\nb", shape="box")
    g.add_node("b", "c", shape="ellipse")
    g.add_edge("a", "b", "x")
    view.draw(g)
    assert set(view.items) == {"n0", "n1"}
    view.highlight({"n1": "#ff9a00"})
    assert len(view._marks) == 1 and view._marks[0].sceneBoundingRect().contains(
        view.items["n1"].sceneBoundingRect().center())


def test_standalone_hosts_need_no_rqt():
    for name in ("mapping_panel", "analysis_panel", "controller_view"):
        done = subprocess.run([sys.executable, str(ROOT / "scripts" / name), "--help"], capture_output=True,
                              text=True, timeout=300)
        assert done.returncode == 0 and "--spec" in done.stdout, done.stderr
    code = ("import sys; import ltl_stack.gui.mapping_panel, ltl_stack.gui.analysis_panel, "
            "ltl_stack.gui.controller_view, ltl_stack.gui.standalone; "
            "print([m for m in sys.modules if m.startswith(('rqt_gui', 'qt_gui'))])")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stdout + done.stderr


def test_combo_boxes_are_named_by_what_and_which_kind(mapping_panel):
    names = {c.objectName() for c in mapping_panel.findChildren(QComboBox)}
    assert "input_object_0_node_combo_box" in names and "output_rightGround_0_topic_combo_box" in names

"""Issue 25: the panels never show a wrong answer without a warning (offscreen, pytest-qt, no master).

Each test names the defect of the issue it covers; each fails on the panels as they were before."""
from __future__ import annotations

import json

import pytest
from gui_data import SIMPLE_MAPPING, SIMPLE_SPEC, simple_snapshot

pytest.importorskip("pytestqt")

from ltl_stack.analysis import cli as analysis_cli  # noqa: E402
from ltl_stack.analysis.snapshot import Snapshot  # noqa: E402
from ltl_stack.gui.analysis_panel import AnalysisPanel  # noqa: E402

WAIT = 60_000  # ms: generous, the machine is busy

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
    assert "/simple/inputs/person has 2 publishers" in text and "/simple/intruder" in text
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

"""A proposition topic of the wrong message type on the live graph is a problem, in ``analyze_graph
--live`` (text and --json) and in the analysis panel (one workflow: ``analysis.workflow.problems``):
the person input published as std_msgs/String, the stop output subscribed as std_msgs/Empty, on a
real master with real rospy nodes."""
from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from test_analysis_live import DATA, run_cli, scenario_on_a_master

pytestmark = pytest.mark.ros

SPEC = Path(__file__).resolve().parents[2] / "config" / "simple" / "simple.structuredslugs"
MAPPING = DATA / "relay_and_tester_mapping.yaml"
EXPECTED = [
    "input person: topic /relay_demo/inputs/person has type std_msgs/String on the graph; a proposition topic "
    "must be std_msgs/Bool",
    "output stop: topic /relay_demo/outputs/stop has type std_msgs/Empty on the graph; a proposition topic must "
    "be std_msgs/Bool",
]


@pytest.fixture(scope="module")
def wrong_types(tmp_path_factory):
    with scenario_on_a_master(tmp_path_factory, "wrong_types") as master:
        yield master


def test_analyze_graph_live_reports_each_wrong_topic_type(wrong_types):
    done = run_cli(wrong_types, "--spec", str(SPEC), "--mapping", str(MAPPING), "--live", "--json")
    assert done.returncode == 0, done.stderr
    problems = json.loads(done.stdout)["problems"]
    typed = [p for p in problems if p["kind"] == "topic type"]
    assert [p["text"] for p in typed] == EXPECTED, problems
    assert all(p["severity"] == "error" for p in typed)
    text = run_cli(wrong_types, "--spec", str(SPEC), "--mapping", str(MAPPING), "--live")
    assert all(line in text.stdout + text.stderr for line in EXPECTED), text.stdout + text.stderr


def test_the_analysis_panel_lists_each_wrong_topic_type(wrong_types, qtbot):
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from ltl_stack.gui.analysis_panel import AnalysisPanel

    panel = AnalysisPanel()
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(SPEC))
    panel.mapping_line_edit.setText(str(MAPPING))
    panel.live_check_box.setChecked(True)
    panel.master_line_edit.setText(wrong_types.uri)
    panel.analyze_push_button.click()
    qtbot.waitUntil(lambda: panel.result is not None or "rror" in panel.status_label.text(), timeout=90_000)
    assert panel.result is not None, panel.status_label.text()
    shown = [panel.problems_list_widget.item(i).text() for i in range(panel.problems_list_widget.count())]
    assert all(any(line in item for item in shown) for line in EXPECTED), shown
    assert "problem(s)" in panel.status_label.text(), panel.status_label.text()

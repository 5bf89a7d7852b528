"""The README's pictures show what today's code shows: they are 1280×800, and the analysis
panel, run now on the graph the picture was made from, shows the same tabs (labels and counts) and the
same problems as ``docs/images/screenshots.json`` says the picture shows. When this fails, make the
pictures again: ``tools/rqt_host.sh run python -m ltl_stack.gui.screenshots``."""
from __future__ import annotations

import json

import pytest
from gui_data import ROOT

pytest.importorskip("pytestqt")
from python_qt_binding.QtGui import QImage  # noqa: E402

from ltl_stack.gui.analysis_panel import AnalysisPanel  # noqa: E402
from ltl_stack.gui.screenshots import GRAPH, SIZE, SOURCE  # noqa: E402

IMAGES = ROOT / "docs" / "images"
PICTURES = ("mapping_panel.png", "analysis_panel.png", "controller_view.png")


def test_the_pictures_are_1280x800_and_linked_from_the_readme():
    shown = json.loads((IMAGES / SOURCE).read_text())
    assert tuple(shown["size"]) == SIZE == (1280, 800)
    readme = (ROOT / "README.md").read_text()
    for name in PICTURES:
        image = QImage(str(IMAGES / name))
        assert (image.width(), image.height()) == SIZE, name
        assert f"docs/images/{name}" in readme


def test_the_analysis_picture_shows_what_the_panel_shows_today(qtbot):
    shown = json.loads((IMAGES / SOURCE).read_text())
    panel = AnalysisPanel(take_snapshot=lambda uri: pytest.fail("the saved graph is used"))
    qtbot.addWidget(panel)
    panel.spec_line_edit.setText(str(ROOT / shown["spec"]))
    panel.mapping_line_edit.setText(str(ROOT / shown["mapping"]))
    panel.snapshot_line_edit.setText(str(IMAGES / GRAPH))
    assert panel.analyze()
    qtbot.waitUntil(lambda: panel.result is not None or "rror" in panel.status_label.text(), timeout=60_000)
    assert panel.result is not None, panel.status_label.text()
    tabs = [panel.findings_tab_widget.tabText(i) for i in range(panel.findings_tab_widget.count())]
    assert tabs == shown["analysis_panel"]["tabs"]
    here = [p.replace(f"{ROOT}/", "") for p in panel.problem_texts()]  # the pictures name files from ROOT
    assert here == shown["analysis_panel"]["problems"]


def test_the_controller_view_picture_shows_todays_counters_line():
    """The counters line of the picture (an executor in normal mode, nothing counted yet) is the one the
    view writes today for the same state (the negotiation counters were added after a picture)."""
    import re

    from ltl_stack.gui.controller_model import StateUpdate, resilience_text

    view = json.loads((IMAGES / SOURCE).read_text())["controller_view"]
    numbers = [int(n) for n in re.findall(r"\d+", view["resilience"])]
    assert numbers and not any(numbers), view["resilience"]  # the picture's executor counted nothing
    assert view["resilience"] == resilience_text(StateUpdate(0, 0, {}, {}, True, mode="normal"))

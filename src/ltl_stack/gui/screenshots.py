"""Screenshots of the three panels on the clean-and-patrol scenario, made by a command, not by hand.

    python -m ltl_stack.gui.screenshots [--out docs/images]
    tools/rqt_host.sh run python -m ltl_stack.gui.screenshots     # drawn with qt_dotgraph, as in rqt

Starts a private master, ``roslaunch``es ``clean_and_patrol.launch`` (simulated robot, proposition
nodes, executor), opens each panel offscreen at a fixed size, drives it as a user would (load and
refresh; analyze the live graph; attach to the executor and wait for it to move) and saves
``mapping_panel.png``, ``analysis_panel.png`` and ``controller_view.png`` at 1280×800 (a laptop
screen, no row made visible that the user would not see), with ``screenshots.json``: what the
pictures show (tab labels, problems, validation lines, states) and the live graph the analysis saw
(``analysis_panel_graph.yaml``), so a test can check that today's code still shows the same. Exit
codes: 0 written, 3 the scenario did not come up, 4 a PNG could not be written.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
import xmlrpc.client
from collections.abc import Callable
from pathlib import Path

from python_qt_binding.QtCore import Qt
from python_qt_binding.QtGui import QImage
from python_qt_binding.QtWidgets import QApplication

from ltl_stack.errors import Exit
from ltl_stack.gui.analysis_panel import AnalysisPanel
from ltl_stack.gui.controller_view import ControllerView
from ltl_stack.gui.mapping_panel import MappingPanel
from ltl_stack.sim.session import RosSession

ROOT = Path(__file__).resolve().parents[3]
CONFIG = Path("config") / "clean_and_patrol"  # relative to ROOT: short paths in the pictures
SIZE = (1280, 800)
SOURCE = "screenshots.json"  # what the pictures show, checked against a fresh run by test_gui_screenshots
GRAPH = "analysis_panel_graph.yaml"  # the live graph the analysis panel's picture was made from
STATE = "/clean_and_patrol/controller_executor/state"


def wait(app, condition: Callable[[], object], timeout: float, what: str) -> None:
    """Process Qt events until ``condition()`` holds; RuntimeError after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise RuntimeError(f"timed out after {timeout:.0f} s waiting for {what}")
        app.processEvents()
        time.sleep(0.02)


def settle(app, seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        app.processEvents()
        time.sleep(0.02)


def save(widget, path: Path) -> None:
    """A PNG of ``widget`` in 256 colours (a third of the size; these pictures have few colours)."""
    image = widget.grab().toImage().convertToFormat(QImage.Format_Indexed8, Qt.ThresholdDither | Qt.AvoidDither)
    if not image.save(str(path), "PNG", 9):
        raise OSError(f"{path}: cannot write the screenshot")
    print(f"screenshots: wrote {path}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="screenshots", description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default=str(ROOT / "docs" / "images"), help="folder for the PNGs")
    args = p.parse_args(argv)
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    os.chdir(ROOT)
    with RosSession() as ros:
        os.environ.update({k: ros.env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME")})
        log = open(ros.workdir / "roslaunch.log", "wb")  # noqa: SIM115 - closed with the session's processes
        ros.start(["roslaunch", "ltl_stack", "clean_and_patrol.launch"], stdout=log)
        app = QApplication.instance() or QApplication(["screenshots"])
        try:
            wait(app, lambda: _published(ros.uri, STATE), 120, "the executor's state topic")
            settle(app, 3.0)  # every proposition node registered
        except RuntimeError as err:
            print(f"screenshots: error: {err}\n{(ros.workdir / 'roslaunch.log').read_text()[-3000:]}", file=sys.stderr)
            return Exit.NO_ROS
        try:
            shown: dict = {"size": list(SIZE), "spec": str(CONFIG / "clean_and_patrol.structuredslugs"),
                           "mapping": str(CONFIG / "clean_and_patrol.yaml")}
            mapping = MappingPanel()
            mapping.resize(*SIZE)
            mapping.spec_line_edit.setText(str(CONFIG / "clean_and_patrol.structuredslugs"))
            mapping.mapping_line_edit.setText(str(CONFIG / "clean_and_patrol.yaml"))
            mapping.launch_line_edit.setText("launch/clean_and_patrol_propositions.launch")
            mapping.show()
            mapping.load()
            mapping.refresh()
            wait(app, lambda: mapping.graph is not None, 60, "the mapping panel's refresh")
            mapping.add_row("stop")  # a second node for stop, not launched yet: a warning on its row
            mapping.combo("output", "stop", 1, "node").setEditText("/brake_controller")
            settle(app, 0.5)
            save(mapping, out / "mapping_panel.png")
            shown["mapping_panel"] = {"validation": [mapping.findings_list_widget.item(i).text()
                                                     for i in range(mapping.findings_list_widget.count())]}

            analysis = AnalysisPanel()
            analysis.resize(*SIZE)
            analysis.spec_line_edit.setText(str(CONFIG / "clean_and_patrol.structuredslugs"))
            analysis.mapping_line_edit.setText(str(CONFIG / "clean_and_patrol.yaml"))
            analysis.live_check_box.setChecked(True)
            analysis.show()
            analysis.analyze()
            wait(app, lambda: analysis.result is not None, 120, "the analysis")
            analysis.findings_tab_widget.setCurrentIndex(1)
            analysis.select_finding("E2", 0)
            analysis.form_combo_box.setCurrentIndex(1)
            analysis.amended_line_edit.setText(str(ros.workdir / "clean_and_patrol_with_suggestions.slugsin"))
            analysis.apply()
            wait(app, lambda: analysis.applied is not None, 120, "apply and check")
            settle(app, 0.5)
            save(analysis, out / "analysis_panel.png")
            analysis.result.snapshot.save(out / GRAPH)
            tabs = analysis.findings_tab_widget
            shown["analysis_panel"] = {"tabs": [tabs.tabText(i) for i in range(tabs.count())],
                                       "problems": analysis.problem_texts(),
                                       "verdict": analysis.verdict_label.text()}

            view = ControllerView()
            view.resize(*SIZE)
            view.spec_line_edit.setText(str(CONFIG / "clean_and_patrol.structuredslugs"))
            view.topic_combo_box.setEditText(STATE)
            view.show()
            view.attach()
            wait(app, lambda: view.model is not None and view.model.current is not None, 120, "the controller view")
            seen = {view.model.current}
            wait(app, lambda: seen.add(view.model.current) or len(seen) >= 3, 120, "the executor moving")
            wait(app, lambda: view.current_node_id() is not None and not view.layout_task.running, 60,
                 "the layout around the current state")
            settle(app, 0.5)
            save(view, out / "controller_view.png")
            shown["controller_view"] = {"states": len(view.model.automaton), "whole": view.model.whole,
                                        "state": view.state_label.text(),
                                        "resilience": view.resilience_label.text()}
            view.shutdown()
            (out / SOURCE).write_text(json.dumps(shown, indent=1) + "\n")
        except OSError as err:
            print(f"screenshots: error: {err}", file=sys.stderr)
            return Exit.WRITE_FAILED
    return Exit.OK


def _published(uri: str, topic: str) -> bool:
    code, _msg, (pubs, _subs, _srv) = xmlrpc.client.ServerProxy(uri).getSystemState("/screenshots")
    return code == 1 and any(name == topic for name, _nodes in pubs)


if __name__ == "__main__":
    sys.exit(main())

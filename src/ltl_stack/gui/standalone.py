"""Standalone hosts of the three panels, for machines without rqt (``rosrun ltl_stack mapping_panel`` ...).

Each host is a ``QApplication`` with one panel, its settings kept in ``QSettings`` (organisation
``ltl_stack``) through the same ``save_settings``/``restore_settings`` the rqt plugins use, and a few
arguments that fill the panel's fields (they win over the saved settings).
"""
from __future__ import annotations

import argparse
import signal
import sys
from collections.abc import Sequence

from python_qt_binding.QtCore import QSettings
from python_qt_binding.QtWidgets import QApplication

from ltl_stack import cli
from ltl_stack.errors import Exit
from ltl_stack.gui.widgets import QSettingsAdapter

PANELS = {
    "mapping_panel": "Proposition mapping panel (thesis Fig. 3.5): map spec propositions to ROS nodes and topics.",
    "analysis_panel": "Conflict analysis panel (thesis Figs. 3.6-3.15): ROS graph checks E1-E3, C1, C2 and "
                      "suggested spec additions.",
    "controller_view": "Live controller view: a running controller_executor's automaton, state, lamps, run/pause.",
}


def build_parser(name: str) -> argparse.ArgumentParser:
    p = cli.ToolParser(name, PANELS[name], exit_codes=(Exit.OK, Exit.BAD_INPUT))
    p.add_argument("--spec", help="the spec file")
    if name in ("mapping_panel", "analysis_panel"):
        p.add_argument("--mapping", help="the mapping YAML")
    if name == "analysis_panel":
        src = p.add_mutually_exclusive_group()
        src.add_argument("--snapshot", help="a saved graph snapshot")
        src.add_argument("--live", action="store_true", help="snapshot the live master")
        p.add_argument("--robots", help="robots for C1/C2, comma separated")
        p.add_argument("--ignore-topics", help="robot topics to ignore, comma separated")
    if name == "controller_view":
        p.add_argument("--state-topic", help="the executor's ~state topic, e.g. /clean_and_patrol/controller_executor/state")
        p.add_argument("--no-robotics-semantics", action="store_true", help="the executor runs without them")
        p.add_argument("--no-cooperative", action="store_true", help="the executor runs without the cooperative strategy")
    p.add_argument("--no-settings", action="store_true", help="neither read nor write the saved settings")
    p.add_argument("--go", action="store_true", help="load / analyze / attach at once")
    return p


def make_panel(name: str):
    """A new panel widget by host name. Only that panel's module is imported: the controller view
    needs rospy and the generated messages, the other two do not."""
    if name == "mapping_panel":
        from ltl_stack.gui.mapping_panel import MappingPanel
        panel = MappingPanel()
        panel.ask_on_close = True  # its own window: closing it with unsaved edits asks
        return panel
    if name == "analysis_panel":
        from ltl_stack.gui.analysis_panel import AnalysisPanel
        return AnalysisPanel()
    from ltl_stack.gui.controller_view import ControllerView
    return ControllerView()


def apply_args(name: str, panel, args: argparse.Namespace) -> None:
    """Fill the panel's fields from the command line."""
    if args.spec:
        panel.spec_line_edit.setText(args.spec)
    if getattr(args, "mapping", None):
        panel.mapping_line_edit.setText(args.mapping)
    if name == "analysis_panel":
        if args.snapshot:
            panel.snapshot_line_edit.setText(args.snapshot)
            panel.live_check_box.setChecked(False)
        if args.live:
            panel.live_check_box.setChecked(True)
        if args.robots:
            panel.robots_line_edit.setText(args.robots)
        if args.ignore_topics:
            panel.ignore_line_edit.setText(args.ignore_topics)
    if name == "controller_view":
        if args.state_topic:
            panel.topic_combo_box.setEditText(args.state_topic)
        if args.no_robotics_semantics:
            panel.robotics_check_box.setChecked(False)
        if args.no_cooperative:
            panel.cooperative_check_box.setChecked(False)
    if args.go:
        {"mapping_panel": lambda: panel.load(), "analysis_panel": lambda: panel.analyze(),
         "controller_view": lambda: panel.attach()}[name]()


def window_size(screen_width: int, screen_height: int) -> tuple[int, int]:
    """1200×800, or less on a smaller screen: the window, frame and title included, fits it."""
    return min(1200, screen_width - 20), min(800, screen_height - 60)


def main(name: str, argv: Sequence[str] | None = None) -> int:
    """Run the standalone host ``name`` (one of ``PANELS``) until its window is closed."""
    args = build_parser(name).parse_args(argv)
    app = QApplication.instance() or QApplication([sys.argv[0]])
    signal.signal(signal.SIGINT, signal.SIG_DFL)  # Ctrl-C closes the window
    panel = make_panel(name)
    settings = None if args.no_settings else QSettingsAdapter(QSettings("ltl_stack", name), "panel")
    if settings is not None:
        panel.restore_settings(settings)
    apply_args(name, panel, args)
    screen = app.primaryScreen()
    size = window_size(screen.availableGeometry().width(), screen.availableGeometry().height()) if screen else (1200, 800)
    panel.resize(*size)
    panel.show()
    code = app.exec_()
    if settings is not None:
        panel.save_settings(settings)
        settings.qsettings.sync()
    if hasattr(panel, "shutdown"):
        panel.shutdown()
    return int(code)

"""The conflict analysis panel (thesis §3.6.1.2, §3.6.2.2, Figs. 3.6–3.9, 3.13–3.15).

Snapshot the live graph or load a saved snapshot, fill in Robots and Robot topics to ignore, Analyze:
one table per check (E1, E2 grouped by topic, E3, C1, C2) with the witness chains; selecting a row
selects every row of its finding (an E2 topic's outputs) and draws the chains' subgraph with the
conflicting channel in red. Each suggested constraint is shown as its Structured English sentence with its formula in words, as
LTL or as ``.slugsin``; "Apply and check" writes the amended spec, synthesizes it and shows whether it is
realizable, or the explanation and the assume-exclusive hint of thesis Example 9. The snapshot, the
analysis and the synthesis run off the GUI thread. All logic is in ``analysis_model``.
"""
from __future__ import annotations

import os
from typing import Any

from python_qt_binding.QtCore import QItemSelection, QItemSelectionModel, QSize, Qt
from python_qt_binding.QtGui import QColor
from python_qt_binding.QtWidgets import (
    QAbstractItemView,
    QCheckBox,
    QFileDialog,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QListWidget,
    QListWidgetItem,
    QPlainTextEdit,
    QPushButton,
    QSplitter,
    QTableView,
    QTabWidget,
    QVBoxLayout,
    QWidget,
)

from ltl_stack.analysis.graph_checks import BY_CODE
from ltl_stack.analysis.report import FEEDBACK_TITLE
from ltl_stack.gui.analysis_model import (
    CHECK_KEYS,
    FEEDBACK_KEY,
    FORM_TITLES,
    FORMS,
    TAB_KEYS,
    TAB_TITLES,
    AnalysisView,
    Table,
    apply_and_check,
    conflict_graph,
    names,
)
from ltl_stack.gui.widgets import (
    ComboBox,
    GraphView,
    RowsModel,
    Task,
    collector_paused,
    docked_hint,
    line_edit,
    restore_controls,
    save_controls,
    show_status,
    status_row,
)
from ltl_stack.gui.worker_process import WorkerProcess, analysis_view


def take_live_snapshot(master_uri: str | None):
    from ltl_stack.ros.graph_snapshot import take_snapshot

    return take_snapshot(master_uri or None)


class AnalysisPanel(QWidget):
    """The panel; ``result`` is the last ``AnalysisView``, ``applied`` the last apply-and-check dict."""

    def __init__(self, parent: QWidget | None = None, take_snapshot=take_live_snapshot):
        super().__init__(parent)
        self.setObjectName("AnalysisPanel")
        self.setWindowTitle("Conflict analysis")
        self.result: AnalysisView | None = None
        self.tables: dict[str, Table] = {}
        self.applied: dict | None = None
        self.task: Task | None = None
        self.layout_task: Task | None = None
        self.layout_count = 0  # Graphviz runs (each finding is laid out once)
        self._pictures: dict[tuple, tuple] = {}  # (result, check, finding) -> (graph, layout)
        self._wanted: tuple | None = None
        self.stale = False  # inputs changed since the result on screen was made
        self._auto_amended = ""  # the amended path the panel filled in (follows the spec until edited)
        self._take_snapshot = take_snapshot
        #: the process the analyses run in (started at the first Analyze; None: on a worker thread here)
        self.analysis_process: WorkerProcess | None = WorkerProcess()
        self._build()
        for edit in (self.spec_line_edit, self.mapping_line_edit, self.snapshot_line_edit, self.master_line_edit,
                     self.robots_line_edit, self.ignore_line_edit):
            edit.textChanged.connect(self._inputs_changed)
        self.live_check_box.toggled.connect(self._inputs_changed)
        self._update_apply()

    # --- layout -----------------------------------------------------------------------------------
    def _build(self) -> None:
        grid = QGridLayout()
        self.spec_line_edit = line_edit("spec_line_edit", "spec file")
        self.mapping_line_edit = line_edit("mapping_line_edit", "mapping YAML")
        self.snapshot_line_edit = line_edit("snapshot_line_edit", "saved snapshot (YAML or JSON)")
        self.live_check_box = QCheckBox("Live graph")
        self.live_check_box.setObjectName("live_check_box")
        self.live_check_box.setToolTip("snapshot the running ROS master instead of reading a file")
        self.master_line_edit = line_edit("master_uri_line_edit", "ROS master (empty: $ROS_MASTER_URI)")
        self.robots_line_edit = line_edit("robots_line_edit", "robots, e.g. sphero_wpw, sphero_ggw")
        self.ignore_line_edit = line_edit("ignore_topics_line_edit", "robot topics to ignore, e.g. /odom, /imu")
        grid.addWidget(QLabel("Spec"), 0, 0)
        grid.addWidget(self.spec_line_edit, 0, 1)
        grid.addWidget(self._browse("spec_browse_push_button", self.spec_line_edit), 0, 2)
        grid.addWidget(QLabel("Mapping"), 1, 0)
        grid.addWidget(self.mapping_line_edit, 1, 1)
        grid.addWidget(self._browse("mapping_browse_push_button", self.mapping_line_edit), 1, 2)
        grid.addWidget(QLabel("Snapshot"), 2, 0)
        grid.addWidget(self.snapshot_line_edit, 2, 1)
        grid.addWidget(self._browse("snapshot_browse_push_button", self.snapshot_line_edit), 2, 2)
        grid.addWidget(self.live_check_box, 2, 3)
        grid.addWidget(QLabel("Master"), 3, 0)
        grid.addWidget(self.master_line_edit, 3, 1)
        grid.addWidget(QLabel("Robots"), 4, 0)
        grid.addWidget(self.robots_line_edit, 4, 1)
        grid.addWidget(QLabel("Robot topics to ignore"), 5, 0)
        grid.addWidget(self.ignore_line_edit, 5, 1)
        self.analyze_push_button = QPushButton("Analyze")
        self.analyze_push_button.setObjectName("analyze_push_button")
        self.analyze_push_button.clicked.connect(self.analyze)
        grid.addWidget(self.analyze_push_button, 4, 2, 2, 2)

        self.findings_tab_widget = QTabWidget()
        self.findings_tab_widget.setObjectName("findings_tab_widget")
        self.models: dict[str, RowsModel] = {}
        self.views: dict[str, QTableView] = {}
        for key in TAB_KEYS:
            view = QTableView()
            view.setObjectName(f"{key.lower()}_table_view")
            view.setSelectionBehavior(QAbstractItemView.SelectRows)
            view.setSelectionMode(QAbstractItemView.ExtendedSelection)
            view.setWordWrap(False)
            view.verticalHeader().setVisible(False)
            view.horizontalHeader().setStretchLastSection(True)
            view.horizontalHeader().setResizeContentsPrecision(50)  # column widths from 50 rows, not all
            model = RowsModel([], view)
            view.setModel(model)
            view.selectionModel().selectionChanged.connect(lambda *_a, k=key: self._on_selection(k))
            self.models[key], self.views[key] = model, view
            self.findings_tab_widget.addTab(view, TAB_TITLES[key])
            self.findings_tab_widget.setTabToolTip(self.findings_tab_widget.count() - 1,
                                                   FEEDBACK_TITLE if key == FEEDBACK_KEY else
                                                   f"{key}: {BY_CODE[key].title}\n{BY_CODE[key].explanation}")
        self.findings_tab_widget.currentChanged.connect(lambda _i: self._on_selection(self.current_key()))
        self.graph_view = GraphView()
        self.graph_view.setObjectName("conflict_graphics_view")

        suggest = QGroupBox("Suggested additions to the specification")
        form_row = QHBoxLayout()
        self.form_combo_box = ComboBox()
        self.form_combo_box.setObjectName("suggestion_form_combo_box")
        self.form_combo_box.addItems([FORM_TITLES[f] for f in FORMS])
        self.form_combo_box.currentIndexChanged.connect(lambda _i: self._show_suggestions())
        self.chosen_line_edit = line_edit("chosen_suggestions_line_edit", "add which, e.g. 1,2 (empty: all)")
        form_row.addWidget(QLabel("Show as"))
        form_row.addWidget(self.form_combo_box)
        form_row.addWidget(self.chosen_line_edit, 1)
        apply_row = QHBoxLayout()
        self.amended_line_edit = line_edit("amended_spec_line_edit", "amended spec to write (.slugsin)")
        self.apply_push_button = QPushButton("Apply and check")
        self.apply_push_button.setObjectName("apply_and_check_push_button")
        self.apply_push_button.clicked.connect(self.apply)
        apply_row.addWidget(self.amended_line_edit, 1)
        apply_row.addWidget(self.apply_push_button)
        self.suggestions_text = QPlainTextEdit()
        self.suggestions_text.setObjectName("suggestions_plain_text_edit")
        self.suggestions_text.setReadOnly(True)
        self.verdict_label = QLabel("")
        self.verdict_label.setObjectName("verdict_label")
        self.verdict_label.setWordWrap(True)
        self.apply_text = QPlainTextEdit()
        self.apply_text.setObjectName("apply_result_plain_text_edit")
        self.apply_text.setReadOnly(True)
        self.apply_text.setPlaceholderText("Apply and check: the amended spec's synthesis result")
        suggest_layout = QVBoxLayout(suggest)
        suggest_layout.addLayout(form_row)
        suggest_layout.addWidget(self.suggestions_text, 3)
        suggest_layout.addLayout(apply_row)
        suggest_layout.addWidget(self.verdict_label)
        suggest_layout.addWidget(self.apply_text, 2)

        bottom_splitter = QSplitter(Qt.Horizontal)
        bottom_splitter.setObjectName("picture_splitter")
        bottom_splitter.addWidget(self.graph_view)
        bottom_splitter.addWidget(suggest)
        bottom_splitter.setSizes([700, 700])
        self.problems_list_widget = QListWidget()
        self.problems_list_widget.setObjectName("problems_list_widget")
        self.problems_list_widget.setToolTip("what analyze_graph reports before its findings: mapping warnings, "
                                             "mapped nodes not in the graph, input topics with several publishers")
        self.problems_list_widget.setMaximumHeight(90)  # set to its lines (up to 4) by _show_problems
        top = QWidget()
        top_layout = QVBoxLayout(top)
        top_layout.setContentsMargins(0, 0, 0, 0)
        top_layout.addWidget(self.problems_list_widget)
        top_layout.addWidget(self.findings_tab_widget, 1)
        main = QSplitter(Qt.Vertical)
        main.setObjectName("main_splitter")
        main.addWidget(top)
        main.addWidget(bottom_splitter)
        main.setSizes([420, 330])

        self.cancel_push_button = QPushButton("Cancel")
        self.cancel_push_button.setObjectName("cancel_push_button")
        self.cancel_push_button.setToolTip("stop waiting for the analysis or the synthesis (its result is dropped)")
        self.cancel_push_button.clicked.connect(self.cancel)
        self.cancel_push_button.hide()
        bottom, self.progress_bar, self.status_label = status_row("Name a spec, a mapping and a snapshot (or tick Live graph), then Analyze.")
        layout = QVBoxLayout(self)
        layout.addLayout(grid)
        layout.addWidget(main, 1)
        bottom.insertWidget(1, self.cancel_push_button)
        layout.addLayout(bottom)

    def _browse(self, name: str, edit: QLineEdit) -> QPushButton:
        button = QPushButton("Browse…")
        button.setObjectName(name)

        def pick() -> None:
            path, _ = QFileDialog.getOpenFileName(self, "Open", edit.text() or os.getcwd())
            if path:
                edit.setText(path)
        button.clicked.connect(pick)
        return button

    # --- analysis -----------------------------------------------------------------------------------
    @property
    def busy(self) -> bool:
        return self.task is not None and self.task.running

    def analyze(self) -> bool:
        """Start the analysis off the GUI thread; False if it cannot start (the reason is shown)."""
        if self.busy:
            return False
        spec, mapping = self.spec_line_edit.text().strip(), self.mapping_line_edit.text().strip()
        snapshot_path = self.snapshot_line_edit.text().strip()
        live = self.live_check_box.isChecked()
        if not spec or not mapping or not (live or snapshot_path):
            self._status("Name a spec, a mapping and a snapshot file (or tick Live graph).", error=True)
            return False
        robots, ignore = names(self.robots_line_edit.text()), names(self.ignore_line_edit.text())
        uri = self.master_line_edit.text().strip() or None
        take, process = self._take_snapshot, self.analysis_process

        def work(progress):
            snapshot = None
            if live:
                progress("taking a snapshot of the ROS master")
                snapshot = take(uri)
            request = {"spec": spec, "mapping": mapping, "snapshot": snapshot,
                       "snapshot_path": None if live else snapshot_path, "robots": robots, "ignore_topics": ignore}
            return analysis_view(process, request, progress)  # in its own process: no GIL shared with the GUI
        self.clear_result()  # a failed run must not leave an older result on screen
        self._start(collector_paused(work), self.show_result, "Analyzing…")
        return True

    def clear_result(self) -> None:
        """Nothing on screen from an earlier run: tables, problems, picture, suggestions, verdict."""
        self.result, self.tables, self.applied, self.stale = None, {}, None, False
        self._pictures, self._wanted = {}, None
        for i, key in enumerate(TAB_KEYS):
            self.models[key].set_rows([], [])
            self.findings_tab_widget.setTabText(i, TAB_TITLES[key])
        self.problems_list_widget.clear()
        self.suggestions_text.clear()
        self.verdict_label.clear()
        self.apply_text.clear()
        self.graph_view.show_message("")
        self.findings_tab_widget.setEnabled(True)
        self._update_apply()

    def _inputs_changed(self, *_args) -> None:
        """An input changed: the result on screen is greyed out and cannot be applied until re-analysed."""
        if self.result is None or self.stale:
            return
        self.stale = True
        self.findings_tab_widget.setEnabled(False)
        self.problems_list_widget.setEnabled(False)
        self.suggestions_text.setEnabled(False)
        self.verdict_label.clear()
        self.apply_text.clear()
        self._update_apply()
        self._status("The inputs changed: the results shown are stale. Analyze again before Apply and check.",
                     error=True)

    def _update_apply(self) -> None:
        self.apply_push_button.setEnabled(not self.busy and self.result is not None and not self.stale)

    def show_result(self, result: AnalysisView) -> None:
        """Fill the problems, the tables, the suggestions and the picture of the first finding."""
        self.result, self.stale = result, False
        for widget in (self.findings_tab_widget, self.problems_list_widget, self.suggestions_text):
            widget.setEnabled(True)
        self._show_problems(result)
        self.tables = result.tables()
        counts = result.counts()
        for i, key in enumerate(TAB_KEYS):
            table = self.tables[key]
            self.models[key].set_rows(table.header, table.rows)
            self.findings_tab_widget.setTabText(i, f"{TAB_TITLES[key]} ({counts[key]})")
            view = self.views[key]
            if len(table.rows) <= 500:  # measuring every row of a huge table costs more than it helps
                view.resizeColumnsToContents()
        self._show_suggestions()
        if self.amended_line_edit.text().strip() in ("", self._auto_amended):  # not typed by the user
            stem = os.path.splitext(result.spec_path)[0]
            self._auto_amended = f"{stem}_with_suggestions.slugsin"
            self.amended_line_edit.setText(self._auto_amended)
        first = next((i for i, k in enumerate(CHECK_KEYS) if self.tables[k].rows), None)
        if first is not None:
            self.findings_tab_widget.setCurrentIndex(first)
            self.select_finding(CHECK_KEYS[first], 0)
        elif result.problems:
            self.graph_view.show_message(f"No findings on what was analysed; {len(result.problems)} problem(s) "
                                         "listed above make it incomplete.")
        else:
            self.graph_view.show_message("No findings.")
        self._update_apply()
        warn = f" {len(result.problems)} problem(s) listed above the tables." if result.problems else ""
        self._status(result.summary() + "." + warn, error=bool(result.problems))

    def _show_problems(self, result: AnalysisView) -> None:
        self.problems_list_widget.clear()
        for p in result.problems:
            item = QListWidgetItem(f"{p.severity}: {p.text}")
            item.setBackground(QColor("#ffc8c8" if p.severity == "error" else "#fff0b0"))
            item.setToolTip(p.text)
            self.problems_list_widget.addItem(item)
        if not result.problems:
            self.problems_list_widget.addItem(QListWidgetItem("No problems: the mapping fits the spec and every "
                                                              "mapped node is in the graph."))
        lines = min(self.problems_list_widget.count(), 4)  # the tables keep the room the problems do not need
        self.problems_list_widget.setMaximumHeight(lines * self.problems_list_widget.sizeHintForRow(0)
                                                   + 2 * self.problems_list_widget.frameWidth() + 4)

    def problem_texts(self) -> list[str]:
        """The problem lines on screen (for tests)."""
        return [p.text for p in self.result.problems] if self.result is not None else []

    def current_key(self) -> str:
        return TAB_KEYS[max(0, self.findings_tab_widget.currentIndex())]

    def select_finding(self, key: str, index: int) -> None:
        """Select every row of finding ``index`` of check ``key`` (and so draw it)."""
        rows = self.tables[key].rows_of(index)
        if not rows:
            return
        model, view = self.models[key], self.views[key]
        selection = QItemSelection(model.index(rows[0], 0), model.index(rows[-1], model.columnCount() - 1))
        view.selectionModel().select(selection, QItemSelectionModel.ClearAndSelect | QItemSelectionModel.Rows)
        view.scrollTo(model.index(rows[0], 0))

    def selected_rows(self, key: str) -> list[int]:
        return sorted({i.row() for i in self.views[key].selectionModel().selectedRows()})

    def _on_selection(self, key: str) -> None:
        if key not in self.tables or self.result is None:
            return
        rows = self.selected_rows(key)
        if not rows:
            return
        table = self.tables[key]
        finding = table.finding[rows[0]]
        wanted = table.rows_of(finding)
        if rows != wanted:  # selecting a row of a finding selects the whole finding (an E2 topic)
            self.select_finding(key, finding)
            return
        self._draw(key, finding)

    def _draw(self, key: str, finding: int) -> None:
        """Draw the finding's chains: laid out by Graphviz off the GUI thread, each finding once (cached);
        a row clicked while a layout runs is drawn when it ends (the newest click wins)."""
        result = self.result
        cached = self._pictures.get((id(result), key, finding))
        if cached is not None:
            self.graph_view.draw(*cached)
            return
        self._wanted = (id(result), key, finding)
        if self.layout_task is not None and self.layout_task.running:
            return
        view = self.graph_view

        def work(_progress):
            graph = conflict_graph(result, key, finding)
            return (id(result), key, finding), graph, (view.layout_for(graph) if graph.nodes else None)
        self.layout_count += 1
        self.layout_task = Task(work, self)
        self.layout_task.finished.connect(self._on_picture)
        self.layout_task.failed.connect(lambda text: view.show_message(text))
        self.layout_task.start()

    def _on_picture(self, done: tuple) -> None:
        wanted, graph, laid_out = done
        if laid_out is not None:
            self._pictures[wanted] = (graph, laid_out)
        if self._wanted != wanted:  # cleared, or another row chosen meanwhile: draw that one
            if self._wanted is not None and self.result is not None and self._wanted[0] == id(self.result):
                self._draw(*self._wanted[1:])
            return
        if laid_out is None:
            self.graph_view.show_message(f"{wanted[1]} {wanted[2] + 1}: nothing to draw (see the table).")
        else:
            self.graph_view.draw(graph, laid_out)

    # --- suggestions --------------------------------------------------------------------------------
    def form(self) -> str:
        return FORMS[max(0, self.form_combo_box.currentIndex())]

    def _show_suggestions(self) -> None:
        if self.result is not None:
            self.suggestions_text.setPlainText(self.result.suggestion_text(self.form()))

    def apply(self) -> bool:
        """Write the amended spec and synthesize it off the GUI thread; False if it cannot start."""
        if self.busy or self.result is None or self.stale:
            self._status("Busy." if self.busy else "Analyze first: no current result (inputs changed or the "
                         "analysis failed).", error=not self.busy)
            return False
        out = self.amended_line_edit.text().strip()
        if not out:
            self._status("Name the amended spec to write.", error=True)
            return False
        chosen_text = self.chosen_line_edit.text().strip()
        try:
            chosen = [int(t) for t in names(chosen_text)] if chosen_text else None
        except ValueError:
            self._status(f"Suggestions to add: {chosen_text!r} is not a list of numbers.", error=True)
            return False
        result = self.result
        self._start(lambda progress: apply_and_check(result, out, chosen, progress), self.show_applied,
                    f"Writing {out} and synthesizing…")
        return True

    def show_applied(self, applied: dict) -> None:
        self.applied = applied
        self.apply_text.setPlainText(applied["text"])
        if applied["realizable"]:
            self.verdict_label.setText(f"Realizable: {applied['output']} can be executed.")
            self.verdict_label.setStyleSheet("color: #006000; font-weight: bold;")
        else:
            hint = applied.get("input_assumption")
            extra = ""
            if hint:
                extra = (" Assuming the inputs " + ", ".join(hint["propositions"]) + " mutually exclusive "
                         + ("restores realizability." if hint["restores_realizability"] else "is not enough."))
            self.verdict_label.setText(f"UNREALIZABLE with the suggestions added.{extra}")
            self.verdict_label.setStyleSheet("color: #a00000; font-weight: bold;")
        self._status(f"Wrote {applied['output']}.")

    # --- plumbing -------------------------------------------------------------------------------------
    def _start(self, work, on_done, text: str) -> None:
        self.task = Task(work, self)
        self.task.progress.connect(lambda t: self._status(t))
        # one slot per outcome: the panel is idle again before the result shows, with nothing left queued
        self.task.finished.connect(lambda result: (self._busy(False), on_done(result)))
        self.task.failed.connect(lambda t: (self._busy(False), self._status(t, error=True)))
        self._busy(True)
        self._status(text)
        self.task.start()

    def cancel(self) -> bool:
        """Stop waiting for the running analysis or apply-and-check; its outcome is dropped (an analysis'
        process is stopped)."""
        if not self.busy:
            return False
        self.task.abandon()
        if self.analysis_process is not None:
            self.analysis_process.kill()
        self._busy(False)
        self._status("Cancelled: nothing from that run is shown or applied.")
        return True

    def _busy(self, busy: bool) -> None:
        self.progress_bar.setVisible(busy)
        self.cancel_push_button.setVisible(busy)
        self.analyze_push_button.setEnabled(not busy)
        self.apply_push_button.setEnabled(not busy and self.result is not None and not self.stale)

    def _status(self, text: str, error: bool = False) -> None:
        show_status(self.status_label, text, error)

    def shutdown(self) -> None:
        """Closed (rqt's shutdown_plugin, or the window): the analysis process ends."""
        if self.analysis_process is not None:
            self.analysis_process.close()

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt's name
        self.shutdown()
        super().closeEvent(event)

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt's name
        return docked_hint(super().sizeHint())

    def save_settings(self, settings: Any) -> None:
        save_controls(self, settings)

    def restore_settings(self, settings: Any) -> None:
        restore_controls(self, settings)

"""The proposition mapping panel (thesis §3.6.1.1, Fig. 3.5 A–E).

Load a spec (its inputs and outputs are listed) and a mapping YAML (or start empty); "Refresh nodes
and topics" reads the live master; each input gets a node drop-down and a topic drop-down filtered to
what that node publishes; each output a ``+`` to add node rows (topic drop-down: what the node
subscribes) and a Delete per row. Findings of ``MappingDocument.validate`` are listed and marked on
the rows as the user edits. Save writes the YAML atomically, keeping what the loaded file said
about ``pkg``/``filename``/``parameters``; "Generate launch file" runs the existing generator.
All logic is in ``mapping_model``; this is the view.
"""
from __future__ import annotations

import copy
import os
from typing import Any

from python_qt_binding.QtCore import Qt, QTimer
from python_qt_binding.QtGui import QColor
from python_qt_binding.QtWidgets import (
    QComboBox,
    QFileDialog,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QListWidget,
    QListWidgetItem,
    QPushButton,
    QSplitter,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from ltl_stack.gui.mapping_model import ERROR, INPUT, OUTPUT, LiveGraph, MappingDocument, launch_file
from ltl_stack.gui.widgets import (
    ComboBox,
    Task,
    ask,
    error_text,
    line_edit,
    restore_controls,
    save_controls,
    show_status,
)

SEVERITY_COLOR = {ERROR: QColor("#ffc8c8"), "warning": QColor("#fff0b0")}


def take_live_graph(master_uri: str | None = None) -> LiveGraph:
    """The master's graph (``ltl_stack.ros.graph_snapshot``; no node is registered)."""
    from ltl_stack.ros.graph_snapshot import take_snapshot

    return LiveGraph(take_snapshot(master_uri or None))


class MappingPanel(QWidget):
    """The panel; ``doc`` is the edited ``MappingDocument`` (None before a spec is loaded)."""

    def __init__(self, parent: QWidget | None = None, take_graph=take_live_graph):
        super().__init__(parent)
        self.setObjectName("MappingPanel")
        self.setWindowTitle("Proposition mapping")
        self.doc: MappingDocument | None = None
        self.graph: LiveGraph | None = None
        self.findings = []
        self.task: Task | None = None
        self._take_graph = take_graph
        self._combos: dict[tuple[str, str, int, str], QComboBox] = {}
        self._filling = False
        self.dirty = False  # edits not saved
        self.ask_on_close = False  # the standalone host asks before a window with edits closes
        self._undo: list[dict] = []  # the rows before each edit
        self._last_edit: tuple | None = None
        self.confirm = lambda title, text: ask(self, title, text)  # Yes/No; tests replace it
        self._build()

    # --- layout -------------------------------------------------------------------------------
    def _build(self) -> None:
        top = QGridLayout()
        self.spec_line_edit = line_edit("spec_line_edit", "spec file (.slugsin, .structuredslugs, ...)")
        self.mapping_line_edit = line_edit("mapping_line_edit", "mapping YAML (empty: start a new mapping)")
        self.launch_line_edit = line_edit("launch_file_line_edit", "launch file to generate")
        self.master_line_edit = line_edit("master_uri_line_edit", "ROS master (empty: $ROS_MASTER_URI)")
        rows = [("Spec", self.spec_line_edit, "spec_browse_push_button"),
                ("Mapping", self.mapping_line_edit, "mapping_browse_push_button"),
                ("Launch file", self.launch_line_edit, "launch_file_browse_push_button"),
                ("Master", self.master_line_edit, None)]
        for r, (label, edit, browse) in enumerate(rows):
            top.addWidget(QLabel(label), r, 0)
            top.addWidget(edit, r, 1)
            if browse:
                button = self._button(browse, "Browse…")
                button.clicked.connect(lambda _=False, e=edit, n=browse: self._browse(e, n))
                top.addWidget(button, r, 2)
        buttons = QHBoxLayout()
        self.load_push_button = self._button("load_push_button", "Load")
        self.refresh_push_button = self._button("refresh_graph_push_button", "Refresh nodes and topics")
        self.save_push_button = self._button("save_push_button", "Save")
        self.generate_push_button = self._button("generate_launch_push_button", "Generate launch file")
        self.undo_push_button = self._button("undo_push_button", "Undo")
        self.undo_push_button.setToolTip("undo the last edit (a node or topic typed or picked, a + or a Delete)")
        self.undo_push_button.setEnabled(False)
        self.undo_push_button.clicked.connect(self.undo)
        for b in (self.load_push_button, self.refresh_push_button, self.save_push_button, self.generate_push_button,
                  self.undo_push_button):
            buttons.addWidget(b)
        buttons.addStretch(1)
        self.load_push_button.clicked.connect(self.load)
        self.refresh_push_button.clicked.connect(self.refresh)
        self.save_push_button.clicked.connect(lambda: self.save())
        self.generate_push_button.clicked.connect(lambda: self.generate_launch())

        self.inputs_table_widget = self._table("inputs_table_widget", ["Input", "Node", "Topic (published)", ""])
        self.outputs_table_widget = self._table("outputs_table_widget",
                                                ["Output", "Node", "Topic (subscribed)", "", ""])
        inputs_box, outputs_box = QGroupBox("Inputs"), QGroupBox("Outputs")
        QVBoxLayout(inputs_box).addWidget(self.inputs_table_widget)
        QVBoxLayout(outputs_box).addWidget(self.outputs_table_widget)
        tables = QSplitter(Qt.Horizontal)  # side by side: each table keeps the panel's height (>= 10 rows)
        tables.setObjectName("tables_splitter")
        self.tables_splitter = tables
        tables.addWidget(inputs_box)
        tables.addWidget(outputs_box)

        self.findings_list_widget = QListWidget()
        self.findings_list_widget.setObjectName("findings_list_widget")
        findings_box = QGroupBox("Validation")
        QVBoxLayout(findings_box).addWidget(self.findings_list_widget)
        main = QSplitter(Qt.Vertical)
        main.setObjectName("main_splitter")
        self.main_splitter = main
        main.addWidget(tables)
        main.addWidget(findings_box)
        main.setStretchFactor(0, 5)
        main.setStretchFactor(1, 1)
        main.setSizes([700, 90])

        self.status_label = QLabel("Load a spec to start.")
        self.status_label.setObjectName("status_label")
        self.status_label.setWordWrap(True)
        layout = QVBoxLayout(self)
        layout.addLayout(top)
        layout.addLayout(buttons)
        layout.addWidget(main, 1)
        layout.addWidget(self.status_label)

    def _button(self, name: str, text: str) -> QPushButton:
        button = QPushButton(text)
        button.setObjectName(name)
        return button

    def _table(self, name: str, header: list[str]) -> QTableWidget:
        table = QTableWidget(0, len(header))
        table.setObjectName(name)
        table.setHorizontalHeaderLabels(header)
        table.verticalHeader().setVisible(False)
        table.verticalHeader().setDefaultSectionSize(26)
        table.horizontalHeader().setStretchLastSection(False)
        return table

    def _browse(self, edit: QLineEdit, name: str) -> None:
        start = edit.text() or os.getcwd()
        if name == "spec_browse_push_button" or name == "mapping_browse_push_button":
            path, _ = QFileDialog.getOpenFileName(self, "Open", start)
        else:
            path, _ = QFileDialog.getSaveFileName(self, "Save as", start)
        if path:
            edit.setText(path)

    # --- actions --------------------------------------------------------------------------------
    def load(self) -> bool:
        """Load the spec and (if named) the mapping; an error is shown, nothing else changes."""
        spec = self.spec_line_edit.text().strip()
        mapping = self.mapping_line_edit.text().strip()
        if not spec:
            self._status("Name a spec file first.", error=True)
            return False
        if self.dirty and not self.confirm("Discard edits?", "The mapping has edits that are not saved. "
                                           "Load anyway and discard them?"):
            self._status("Load cancelled: the edits are kept.")
            return False
        try:
            doc = MappingDocument.load(spec, mapping or None)
        except Exception as err:  # noqa: BLE001 - shown to the user
            self._status(error_text(err), error=True)
            return False
        self.doc = doc
        self.dirty, self._undo = False, []
        self.undo_push_button.setEnabled(False)
        self.rebuild()
        self._status(f"Loaded {len(doc.inputs)} inputs and {len(doc.outputs)} outputs from {spec}"
                     + (f" and the mapping {mapping}." if mapping else "; no mapping (new)."))
        return True

    def refresh(self) -> None:
        """Read the master's nodes and topics off the GUI thread, then refill the drop-downs."""
        if self.task is not None and self.task.running:
            return
        uri = self.master_line_edit.text().strip() or None
        self.task = Task(lambda progress: self._take_graph(uri), self)
        # one slot per outcome, so nothing is left queued once the result shows
        self.task.finished.connect(lambda graph: (self.refresh_push_button.setEnabled(True), self._on_graph(graph)))
        self.task.failed.connect(lambda text: (self.refresh_push_button.setEnabled(True),
                                               self._status(f"Refresh failed: {text}", error=True)))
        self.refresh_push_button.setEnabled(False)
        self._status("Reading nodes and topics from the master…")
        self.task.start()

    def _on_graph(self, graph: LiveGraph) -> None:
        self.graph = graph
        self.rebuild()
        self._status(f"Master: {len(graph.nodes)} nodes, {len(graph.topics)} topics.")

    def save(self, path: str | None = None) -> bool:
        if self.doc is None:
            self._status("Nothing to save: load a spec first.", error=True)
            return False
        errors = self.errors()
        if errors and not self.confirm("Save with errors?", f"{len(errors)} error(s) are listed, the first: "
                                       f"{errors[0].message}\nSave anyway?"):
            self._status(f"Not saved: {len(errors)} error(s) listed.", error=True)
            return False
        path = path or self.mapping_line_edit.text().strip()
        if not path:
            path, _ = QFileDialog.getSaveFileName(self, "Save mapping", os.getcwd(), "YAML (*.yaml *.yml)")
            if not path:
                return False
        try:
            self.doc.save(path)
        except Exception as err:  # noqa: BLE001 - the spec named as output, a folder that cannot be written
            self._status(error_text(err), error=True)
            return False
        self.dirty = False
        self.mapping_line_edit.setText(path)
        self._status(f"Saved {path}.")
        return True

    def generate_launch(self, out: str | None = None) -> bool:
        if self.doc is None:
            self._status("Load a spec and a mapping first.", error=True)
            return False
        out = out or self.launch_line_edit.text().strip()
        if not out:
            self._status("Name the launch file to write.", error=True)
            return False
        errors = self.errors()
        if errors:  # a launch file from a wrong mapping starts wrong nodes (a second camera, ...)
            self._status(f"No launch file: fix the {len(errors)} error(s) listed first ({errors[0].message}).",
                         error=True)
            return False
        if not self.save():
            return False
        try:
            warnings = launch_file(self.doc, out)
        except Exception as err:  # noqa: BLE001 - shown to the user
            self._status(error_text(err), error=True)
            return False
        self.launch_line_edit.setText(out)
        self._status(f"Wrote {out}" + (f" ({len(warnings)} warnings: {warnings[0]} …)" if warnings else "."))
        return True

    # --- the tables -------------------------------------------------------------------------------
    def rebuild(self) -> None:
        """Lay the rows out again (after a load, a refresh, a + or a Delete)."""
        tables = (self.inputs_table_widget, self.outputs_table_widget)
        scroll = [(t.verticalScrollBar().value(), t.horizontalScrollBar().value()) for t in tables]
        self._filling = True
        self._combos = {}
        try:
            self._fill(self.inputs_table_widget, INPUT)
            self._fill(self.outputs_table_widget, OUTPUT)
        finally:
            self._filling = False
        for table, (v, h) in zip(tables, scroll):  # + and Delete keep the user's place
            table.verticalScrollBar().setValue(v)
            table.horizontalScrollBar().setValue(h)
        self.validate()

    def _fill(self, table: QTableWidget, kind: str) -> None:
        table.setRowCount(0)
        if self.doc is None:
            return
        for prop in self.doc.propositions(kind):
            rows = self.doc.rows[(kind, prop)]
            for i in range(max(1, len(rows))):
                r = table.rowCount()
                table.insertRow(r)
                item = QTableWidgetItem(prop if i == 0 else "")
                item.setFlags(Qt.ItemIsEnabled)
                table.setItem(r, 0, item)
                if i < len(rows):
                    self._row_widgets(table, r, kind, prop, i)
                if kind == OUTPUT and i == 0:
                    add = self._button(f"{prop}_add_push_button", "+")
                    add.setToolTip(f"add a node for {prop}")
                    add.clicked.connect(lambda _=False, p=prop: self.add_row(p))
                    table.setCellWidget(r, 4, add)
        header = table.horizontalHeader()
        for column in range(table.columnCount()):
            header.setSectionResizeMode(column, QHeaderView.Stretch if column == 2
                                        else QHeaderView.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.Interactive)
        table.setColumnWidth(1, 170)  # two tables side by side at 1280 px: the topic column keeps room

    def _row_widgets(self, table: QTableWidget, r: int, kind: str, prop: str, i: int) -> None:
        row = self.doc.rows[(kind, prop)][i]
        node = self._combo(f"{kind}_{prop}_{i}_node_combo_box", self.graph.nodes if self.graph else [], row.node)
        topics = self.graph.topics_for(kind, self.doc.resolved_node(kind, row.node, self.graph)) \
            if self.graph and row.node else []
        topic = self._combo(f"{kind}_{prop}_{i}_topic_combo_box", topics, row.topic)
        node.currentTextChanged.connect(lambda text, k=kind, p=prop, n=i: self._on_node(k, p, n, text))
        topic.currentTextChanged.connect(lambda text, k=kind, p=prop, n=i: self._on_topic(k, p, n, text))
        node.activated.connect(lambda _i, k=kind, p=prop, n=i: self._on_pick(k, p, n, "node"))
        topic.activated.connect(lambda _i, k=kind, p=prop, n=i: self._on_pick(k, p, n, "topic"))
        self._combos[(kind, prop, i, "node")] = node
        self._combos[(kind, prop, i, "topic")] = topic
        table.setCellWidget(r, 1, node)
        table.setCellWidget(r, 2, topic)
        delete = self._button(f"{kind}_{prop}_{i}_delete_push_button", "Delete")
        delete.clicked.connect(lambda _=False, k=kind, p=prop, n=i: self.delete_row(k, p, n))
        table.setCellWidget(r, 3, delete)

    def _combo(self, name: str, items: list[str], text: str) -> QComboBox:
        combo = ComboBox()
        combo.setObjectName(name)
        combo.setEditable(True)
        combo.setInsertPolicy(QComboBox.NoInsert)
        combo.addItems(items)
        combo.setEditText(text)
        return combo

    def combo(self, kind: str, prop: str, index: int, which: str) -> QComboBox:
        """The node or topic drop-down of a row (``which`` is ``node`` or ``topic``)."""
        return self._combos[(kind, prop, index, which)]

    def _on_pick(self, kind: str, prop: str, i: int, which: str) -> None:
        """A name picked from the master's list: written relative when the mapping is relative."""
        combo = self._combos[(kind, prop, i, which)]
        short = self.doc.relative_name(kind, which, combo.currentText().strip()) if self.doc else ""
        if short and short != combo.currentText().strip():
            combo.setEditText(short)

    def _remember(self, key: tuple | None = None) -> None:
        """Keep the rows as they are before an edit, for Undo (typing into one field is one edit)."""
        if key is None or key != self._last_edit:
            self._undo.append(copy.deepcopy(self.doc.rows))
            del self._undo[:-100]
        self._last_edit = key
        self.dirty = True
        self.undo_push_button.setEnabled(True)

    def undo(self) -> None:
        """Put the rows back as they were before the last edit."""
        if self.doc is None or not self._undo:
            return
        self.doc.rows = self._undo.pop()
        self._last_edit = None
        self.undo_push_button.setEnabled(bool(self._undo))
        self.rebuild()
        self._status("Undone.")

    def errors(self) -> list:
        """The errors listed now (validation runs first, so the list is current)."""
        return [f for f in self.validate() if f.severity == ERROR]

    def _on_node(self, kind: str, prop: str, i: int, text: str) -> None:
        if self._filling or self.doc is None:
            return
        self._remember((kind, prop, i, "node"))
        self.doc.set_node(kind, prop, i, text)
        topic = self._combos[(kind, prop, i, "topic")]
        if self.graph is not None:
            current = topic.currentText()
            self._filling = True
            try:
                topic.clear()
                topic.addItems(self.graph.topics_for(kind, self.doc.resolved_node(kind, text, self.graph)))
                topic.setEditText(current)
            finally:
                self._filling = False
        self._schedule_validation()

    def _on_topic(self, kind: str, prop: str, i: int, text: str) -> None:
        if self._filling or self.doc is None:
            return
        self._remember((kind, prop, i, "topic"))
        self.doc.set_topic(kind, prop, i, text)
        self._schedule_validation()

    def _schedule_validation(self) -> None:
        QTimer.singleShot(0, self.validate)

    def add_row(self, prop: str) -> None:
        if self.doc is not None:
            self._remember()
            self.doc.add_row(prop)
            self.rebuild()

    def delete_row(self, kind: str, prop: str, index: int) -> None:
        if self.doc is not None:
            self._remember()
            self.doc.delete_row(kind, prop, index)
            self.rebuild()

    # --- validation -------------------------------------------------------------------------------
    def validate(self) -> list:
        """Run the checks and mark them: the list below the tables, colours and tooltips on the rows."""
        if self.doc is None:
            return []
        self.findings = self.doc.validate(self.graph)
        self.findings_list_widget.clear()
        marks: dict[tuple[str, str, int], tuple[str, str]] = {}
        for f in self.findings:
            item = QListWidgetItem(str(f))
            item.setBackground(SEVERITY_COLOR.get(f.severity, QColor("white")))
            self.findings_list_widget.addItem(item)
            key = (f.kind, f.proposition, max(f.row, 0))
            if key not in marks or f.severity == ERROR:
                marks[key] = (f.severity, f.message)
        for (kind, prop, i, _which), combo in self._combos.items():
            mark = marks.get((kind, prop, i))
            if mark is None:
                combo.setStyleSheet("")
                combo.setToolTip("")
            else:
                combo.setStyleSheet(f"QComboBox {{ background: {SEVERITY_COLOR[mark[0]].name()}; }}")
                combo.setToolTip(mark[1])
        if not self.findings:
            self.findings_list_widget.addItem(QListWidgetItem("No problems found."))
        return self.findings

    def _status(self, text: str, error: bool = False) -> None:
        show_status(self.status_label, text, error)

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt's name
        """Closing a standalone window with unsaved edits asks first (``ask_on_close``, set by the host;
        rqt closes its plugins without asking)."""
        if self.ask_on_close and self.dirty and not self.confirm("Discard edits?", "The mapping has edits that are not saved. "
                                           "Close anyway and discard them?"):
            event.ignore()
            return
        event.accept()

    # --- settings (rqt's save_settings / restore_settings) -----------------------------------------
    def save_settings(self, settings: Any) -> None:
        save_controls(self, settings)

    def restore_settings(self, settings: Any) -> None:
        restore_controls(self, settings)
        if self.spec_line_edit.text().strip() and os.path.isfile(self.spec_line_edit.text().strip()):
            self.load()

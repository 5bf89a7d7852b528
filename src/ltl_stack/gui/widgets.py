"""Qt pieces the three panels share: a background task, a table model, a graph view, settings.

Only ``python_qt_binding`` is imported here. The graph view draws with ``qt_dotgraph`` (as rqt_graph
does) when it is importable and with its own items from Graphviz's ``-Tplain`` layout otherwise; both
draw the same ``DotGraph`` and can highlight its nodes without a new layout.
"""
from __future__ import annotations

import gc
import math
import os
import sys
import threading
import traceback
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from python_qt_binding.QtCore import (
    QAbstractTableModel,
    QModelIndex,
    QObject,
    QPointF,
    QRectF,
    QSize,
    Qt,
    Signal,
    Slot,
)
from python_qt_binding.QtGui import QBrush, QColor, QFont, QImage, QPainter, QPainterPath, QPen, QPolygonF
from python_qt_binding.QtWidgets import (
    QAbstractButton,
    QAbstractItemView,
    QCheckBox,
    QComboBox,
    QFileDialog,
    QGraphicsEllipseItem,
    QGraphicsPathItem,
    QGraphicsPolygonItem,
    QGraphicsRectItem,
    QGraphicsScene,
    QGraphicsSimpleTextItem,
    QGraphicsView,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QMenu,
    QMessageBox,
    QPlainTextEdit,
    QProgressBar,
    QSpinBox,
    QSplitter,
    QTabWidget,
    QWidget,
)

from ltl_stack.cli import write_output
from ltl_stack.errors import UserError
from ltl_stack.gui.dotgraph import DotGraph, GraphvizError, PlainLayout, layout_dot, layout_plain, render

try:  # the renderer rqt_graph uses; absent where rqt is not installed
    from qt_dotgraph.dot_to_qt import DotToQtGenerator
except ImportError:
    DotToQtGenerator = None


HOVER_COLOR = "#7b3fb5"  # a hovered node: not red (a conflict), blue (a proposition node) or green (initial)

def error_text(err: BaseException) -> str:
    """One line for the user: a ``UserError``'s message, else the exception's type and message."""
    if isinstance(err, (UserError, OSError, GraphvizError)):
        return str(err)
    return f"{type(err).__name__}: {err}"


class ComboBox(QComboBox):
    """A drop-down that takes the mouse wheel only when it has the focus (clicked or tabbed to):
    scrolling a table or a panel over it scrolls that and never changes the value."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setFocusPolicy(Qt.StrongFocus)

    def wheelEvent(self, event) -> None:  # noqa: N802 - Qt's name
        if self.hasFocus():
            super().wheelEvent(event)
        else:
            event.ignore()  # to the parent: the table or panel scrolls


class SpinBox(QSpinBox):
    """A spin box with ``ComboBox``'s wheel rule."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setFocusPolicy(Qt.StrongFocus)

    def wheelEvent(self, event) -> None:  # noqa: N802
        if self.hasFocus():
            super().wheelEvent(event)
        else:
            event.ignore()


def ask(parent: QWidget, title: str, text: str) -> bool:
    """Yes/No question (No is the default); panels hold it in ``confirm`` so tests can answer it."""
    answer = QMessageBox.question(parent, title, text, QMessageBox.Yes | QMessageBox.No, QMessageBox.No)
    return answer == QMessageBox.Yes


def line_edit(name: str, placeholder: str) -> QLineEdit:
    """A line edit with an object name (for settings and tests) and a placeholder saying what goes in."""
    edit = QLineEdit()
    edit.setObjectName(name)
    edit.setPlaceholderText(placeholder)
    return edit


def status_row(text: str) -> tuple[QHBoxLayout, QProgressBar, QLabel]:
    """A panel's bottom row: a busy indicator (hidden until work runs) and the status line."""
    progress = QProgressBar()
    progress.setObjectName("progress_bar")
    progress.setRange(0, 0)
    progress.setMaximumWidth(160)
    progress.hide()
    label = QLabel(text)
    label.setObjectName("status_label")
    label.setWordWrap(True)
    row = QHBoxLayout()
    row.addWidget(progress)
    row.addWidget(label, 1)
    return row, progress, label


def show_status(label: QLabel, text: str, error: bool = False) -> None:
    """Put ``text`` on a status line, in red when it reports an error."""
    label.setText(text)
    label.setStyleSheet("color: #a00000;" if error else "")


class _Relay(QObject):
    """Carries a worker thread's outcome to the GUI thread. The worker emits on this object, which lives
    as long as the process, never on the task itself: a panel closed meanwhile deletes the task on the
    GUI thread, and a signal emitted from another thread on an object being deleted crashes the process
    (seen: a segfault in a test's teardown). On the GUI thread, a deleted task is simply skipped."""

    deliver = Signal(object, str, object)  # task, the name of its _deliver_* slot, the value

    def __init__(self) -> None:
        super().__init__()
        self.deliver.connect(self._deliver)  # emitted from worker threads: queued to this object's thread

    @Slot(object, str, object)
    def _deliver(self, task: Any, name: str, value: object) -> None:
        try:
            getattr(task, name)(value)
        except RuntimeError:  # the panel was closed and the task deleted while the work ran
            pass


_RELAY: _Relay | None = None


def _relay() -> _Relay:
    """The process' one relay, made on the GUI thread by the first task (tasks are made there)."""
    global _RELAY
    if _RELAY is None:
        _RELAY = _Relay()
    return _RELAY


#: Python's GIL switch interval while a background task runs (the default is 5 ms).
HANDOVER_INTERVAL_S = 0.0002
_handover = {"running": 0, "saved": 0.005}
_handover_lock = threading.Lock()


@contextmanager
def quick_handover() -> Iterator[None]:
    """While any background task runs, the GIL changes hands every 0.2 ms instead of every 5 ms.

    PyQt takes the GIL for every event it hands to Python (slots, models, reimplemented handlers). With a
    worker thread running Python code, each of those waits until the worker is asked to let go: up to the
    switch interval, 5 ms by default, and a repaint needs dozens of them. That was the analysis panel's
    GUI-thread stalls (300 ms with the machine idle; 41 ms at 0.2 ms, `bench_gui.py --pictures`, and
    py-spy showed the GUI thread waiting for the GIL inside Qt's event dispatch). The interval is set
    back when the last task ends. Process-wide, as the interval is; work is not slowed (the worker only
    hands over when the GUI thread asks)."""
    with _handover_lock:
        if _handover["running"] == 0:
            _handover["saved"] = sys.getswitchinterval()
            sys.setswitchinterval(min(HANDOVER_INTERVAL_S, _handover["saved"]))
        _handover["running"] += 1
    try:
        yield
    finally:
        with _handover_lock:
            _handover["running"] -= 1
            if _handover["running"] == 0:
                sys.setswitchinterval(_handover["saved"])


_collector = {"paused_by": 0, "was_enabled": True}
_collector_lock = threading.Lock()


def collector_paused(work: Callable[[Callable[[str], None]], Any]) -> Callable[[Callable[[str], None]], Any]:
    """``work`` with Python's cyclic garbage collector paused while it runs, then everything alive frozen
    (``gc.freeze``; reference counting still frees it). A full collection holds the GIL for as long as it
    walks every object: during the analysis of a 10,000-node graph that was 90-500 ms on the worker thread,
    and the GUI thread waited for it (bench_gui --pictures). For work that makes no reference cycles
    (the analysis: a collection after it finds none), so nothing is left for the collector."""
    def run(progress: Callable[[str], None]) -> Any:
        with _collector_lock:
            if _collector["paused_by"] == 0:
                _collector["was_enabled"] = gc.isenabled()
                gc.disable()
            _collector["paused_by"] += 1
        try:
            return work(progress)
        finally:
            with _collector_lock:
                _collector["paused_by"] -= 1
                if _collector["paused_by"] == 0 and _collector["was_enabled"]:
                    gc.freeze()  # what survived is not walked by the next full collections
                    gc.enable()
    return run


class Cancelled(Exception):
    """Raised in a task's work by its ``progress`` callback once the task was cancelled: long work stops at
    its next progress report instead of running to the end for nothing."""


class Task(QObject):
    """Run ``work(progress)`` on a Python thread; its signals arrive on the GUI thread.

    ``progress(text)`` may be called from the work; ``finished`` carries the result, ``failed`` the
    error text. Both are emitted on the GUI thread by one queued delivery that first marks the task
    settled, so a panel's slots run in the same event as ``running`` turning False (nobody sees an idle
    panel without its result). Keep a reference to the task until it has finished.

    After ``abandon`` the work's next ``progress`` call raises ``Cancelled``; a result that arrives anyway
    is handed to ``discard`` (on the GUI thread), so what the work opened can be closed.
    """

    progress = Signal(str)
    finished = Signal(object)
    failed = Signal(str)

    def __init__(self, work: Callable[[Callable[[str], None]], Any], parent: QObject | None = None,
                 discard: Callable[[Any], None] | None = None):
        super().__init__(parent)
        self._work = work
        self._discard = discard
        self.thread: threading.Thread | None = None
        self._pending = False
        self._abandoned = False
        self._relay = _relay()

    def start(self) -> None:
        self._pending = True
        self.thread = threading.Thread(target=self._run, name="ltl_stack_gui_task", daemon=True)
        self.thread.start()

    def abandon(self) -> None:
        """Cancel: the work cannot be stopped (a Python thread), but its outcome is never delivered and
        the task stops counting as running at once."""
        self._abandoned, self._pending = True, False

    @Slot(object)
    def _deliver_done(self, result: object) -> None:
        self._pending = False
        if not self._abandoned:
            self.finished.emit(result)
        elif self._discard is not None:
            self._discard(result)

    @Slot(str)
    def _deliver_error(self, text: str) -> None:
        self._pending = False
        if not self._abandoned:
            self.failed.emit(text)

    def _run(self) -> None:
        try:
            with quick_handover():
                result = self._work(self._progress)
        except Exception as err:  # noqa: BLE001 - every failure is shown in the panel, none kills it
            if not isinstance(err, (UserError, OSError, GraphvizError, Cancelled)):
                traceback.print_exc()
            self._relay.deliver.emit(self, "_deliver_error", error_text(err))
            return
        self._relay.deliver.emit(self, "_deliver_done", result)

    def _progress(self, text: str) -> None:
        if self._abandoned:
            raise Cancelled(text)
        self._relay.deliver.emit(self, "_deliver_progress", text)

    @Slot(str)
    def _deliver_progress(self, text: str) -> None:
        if not self._abandoned:
            self.progress.emit(text)

    @property
    def running(self) -> bool:
        """Started and its outcome not yet delivered on the GUI thread (the worker thread may have
        ended already, or may still be winding down after delivering)."""
        return self._pending


class RowsModel(QAbstractTableModel):
    """A read-only table over a list of string rows; ``backgrounds`` colours whole rows."""

    def __init__(self, header: Sequence[str] = (), parent: QObject | None = None):
        super().__init__(parent)
        self.header = list(header)
        self.rows: list[Sequence[str]] = []
        self.tooltips: list[str] = []
        self.backgrounds: dict[int, QColor] = {}

    def set_rows(self, header: Sequence[str], rows: Sequence[Sequence[str]], tooltips: Sequence[str] = ()) -> None:
        self.beginResetModel()
        self.header = list(header)
        self.rows = list(rows)
        self.tooltips = list(tooltips)
        self.backgrounds = {}
        self.endResetModel()

    def rowCount(self, parent: QModelIndex = QModelIndex()) -> int:  # noqa: B008, N802 - Qt's signature
        return 0 if parent.isValid() else len(self.rows)

    def columnCount(self, parent: QModelIndex = QModelIndex()) -> int:  # noqa: B008, N802
        return 0 if parent.isValid() else len(self.header)

    def data(self, index: QModelIndex, role: int = Qt.DisplayRole) -> Any:
        if not index.isValid():
            return None
        if role == Qt.DisplayRole:
            row = self.rows[index.row()]
            return row[index.column()] if index.column() < len(row) else ""
        if role == Qt.ToolTipRole:  # made when asked: a table may have tens of thousands of rows
            if index.row() < len(self.tooltips) and self.tooltips[index.row()]:
                return self.tooltips[index.row()]
            return " / ".join(c for c in self.rows[index.row()] if c)
        if role == Qt.BackgroundRole and index.row() in self.backgrounds:
            return QBrush(self.backgrounds[index.row()])
        return None

    def headerData(self, section: int, orientation: int, role: int = Qt.DisplayRole) -> Any:  # noqa: N802
        if role == Qt.DisplayRole and orientation == Qt.Horizontal and section < len(self.header):
            return self.header[section]
        return None


class GraphView(QGraphicsView):
    """Draws a ``DotGraph``; ``highlight`` fills chosen nodes without laying the graph out again."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setToolTip("wheel: zoom; drag: move; right-click: fit, zoom, save as PNG/SVG/DOT")
        self.setScene(QGraphicsScene(self))
        self.setRenderHints(QPainter.Antialiasing | QPainter.TextAntialiasing)
        self.setDragMode(QGraphicsView.ScrollHandDrag)
        self.renderer = "qt_dotgraph" if DotToQtGenerator is not None else "plain"
        self.graph: DotGraph | None = None
        self.items: dict[str, Any] = {}  # node id -> the item drawn for it
        self._marks: list[QGraphicsRectItem] = []

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt's name; without it splitters squeeze the picture
        return QSize(640, 420)

    def show_message(self, text: str) -> None:
        self.scene().clear()
        self.items, self._marks, self.graph = {}, [], None
        item = self.scene().addSimpleText(text)
        item.setBrush(QBrush(QColor("dimgray")))
        self.scene().setSceneRect(item.boundingRect())

    def draw(self, graph: DotGraph, laid_out: Any = None) -> None:
        """Draw ``graph``; ``laid_out`` is a layout made off the GUI thread by ``layout_for`` (or a
        ``PlainLayout`` such as ``sketch_layout``'s, drawn by the plain renderer whatever this view's is)."""
        if laid_out is None:
            laid_out = self.layout_for(graph)
        scene = self.scene()
        scene.clear()
        self.items, self._marks, self.graph = {}, [], graph
        if self.renderer == "qt_dotgraph" and not isinstance(laid_out, PlainLayout):
            nodes, _edges = DotToQtGenerator().dotcode_to_qt_items(laid_out, 1, scene=scene)
            self.items = {name.strip('"'): item for name, item in nodes.items()}
            for item in self.items.values():  # qt_dotgraph hovers in red: the panels' conflict colour
                item._COLOR_RED = QColor(HOVER_COLOR)
        else:
            self.items = _draw_plain(scene, laid_out)
        scene.setSceneRect(scene.itemsBoundingRect().adjusted(-10, -10, 10, 10))
        self.fit()

    def layout_for(self, graph: DotGraph) -> Any:
        """The layout this view's renderer draws (runs Graphviz; safe on any thread)."""
        text = graph.to_dot()
        return layout_dot(text) if self.renderer == "qt_dotgraph" else layout_plain(text)

    def fit(self) -> None:
        rect = self.scene().sceneRect()
        if rect.width() > 0 and rect.height() > 0:
            self.fitInView(rect, Qt.KeepAspectRatio)
            if self.transform().m11() > 1.5:  # do not blow small graphs up
                self.resetTransform()
                self.scale(1.5, 1.5)

    def highlight(self, marks: dict[str, str]) -> None:
        """Fill the nodes with these ids (``{id: colour}``) behind their outline; others plain."""
        for mark in self._marks:
            self.scene().removeItem(mark)
        self._marks = []
        for node_id, color in marks.items():
            item = self.items.get(node_id)
            if item is None:
                continue
            rect = item.sceneBoundingRect().adjusted(-3, -3, 3, 3)
            mark = self.scene().addRect(rect, QPen(QColor(color), 2), QBrush(QColor(color).lighter(160)))
            mark.setZValue(-1)
            self._marks.append(mark)

    def center_on_node(self, node_id: str) -> None:
        item = self.items.get(node_id)
        if item is not None:
            self.ensureVisible(item.sceneBoundingRect(), 40, 40)

    def wheelEvent(self, event) -> None:  # noqa: N802 - Qt's name
        self.zoom(1.15 if event.angleDelta().y() > 0 else 1 / 1.15)

    def zoom(self, factor: float) -> None:
        self.scale(factor, factor)

    def contextMenuEvent(self, event) -> None:  # noqa: N802 - Qt's name
        menu = QMenu(self)
        menu.addAction("Fit to view", self.fit)
        menu.addAction("Zoom in", lambda: self.zoom(1.25))
        menu.addAction("Zoom out", lambda: self.zoom(0.8))
        menu.addAction("Actual size", self.resetTransform)
        save = menu.addAction("Save as PNG, SVG or DOT…", self.save_dialog)
        save.setEnabled(self.graph is not None)
        menu.exec_(event.globalPos())

    def save_dialog(self) -> None:
        path, _ = QFileDialog.getSaveFileName(self, "Save the picture", f"{self.graph.name if self.graph else 'graph'}.png",
                                              "PNG (*.png);;SVG (*.svg);;Graphviz DOT (*.dot)")
        if path:
            try:
                self.save(path)
            except (OSError, GraphvizError, ValueError) as err:
                self.show_message(error_text(err))

    def save(self, path: str) -> None:
        """The picture to ``path`` by its extension: ``.png`` as drawn (with the highlight), ``.svg``
        by Graphviz from the same graph, ``.dot`` the graph itself (rqt_graph's three formats)."""
        if self.graph is None:
            raise ValueError("nothing is drawn")
        ext = os.path.splitext(path)[1].lower()
        if ext == ".dot":
            write_output(path, self.graph.to_dot(), "DOT file")
        elif ext == ".svg":
            write_output(path, render(self.graph.to_dot(), "svg"), "SVG file")
        elif ext == ".png":
            rect = self.scene().sceneRect()
            image = QImage(int(rect.width()) + 1, int(rect.height()) + 1, QImage.Format_ARGB32)
            image.fill(QColor("white"))
            painter = QPainter(image)
            painter.setRenderHints(QPainter.Antialiasing | QPainter.TextAntialiasing)
            self.scene().render(painter, QRectF(image.rect()), rect)
            painter.end()
            if not image.save(path, "PNG"):
                raise OSError(f"cannot write {path}")
        else:
            raise ValueError(f"{path}: save as .png, .svg or .dot")


_DPI = 72.0


def _draw_plain(scene: QGraphicsScene, layout) -> dict[str, Any]:
    """Items for Graphviz's plain layout (inches, y up) in points with y down, as qt_dotgraph draws."""
    items = {}
    font = QFont("Helvetica", 9)

    def pt(x: float, y: float) -> QPointF:
        return QPointF(x * _DPI, (layout.height - y) * _DPI)

    for node in layout.nodes.values():
        w, h = node.width * _DPI, node.height * _DPI
        c = pt(node.x, node.y)
        rect = QRectF(c.x() - w / 2, c.y() - h / 2, w, h)
        shape = QGraphicsEllipseItem(rect) if node.shape in ("ellipse", "oval", "circle") else QGraphicsRectItem(rect)
        shape.setPen(QPen(QColor(node.color if node.color != "black" else "#000000")))
        scene.addItem(shape)
        text = QGraphicsSimpleTextItem(node.label.replace("\\n", "\n"))
        text.setFont(font)
        text.setBrush(QBrush(QColor(node.color)))
        br = text.boundingRect()
        text.setPos(c.x() - br.width() / 2, c.y() - br.height() / 2)
        scene.addItem(text)
        items[node.id] = shape
    for edge in layout.edges:
        if len(edge.points) < 2:
            continue
        pts = [pt(x, y) for x, y in edge.points]
        path = QPainterPath(pts[0])
        for i in range(1, len(pts) - 2, 3):  # a B-spline: the start, then three points per segment
            path.cubicTo(pts[i], pts[i + 1], pts[i + 2])
        pen = QPen(QColor(edge.color))
        scene.addItem(_path_item(path, pen))
        scene.addItem(_arrow(pts[-2], pts[-1], QColor(edge.color)))
        if edge.label and edge.label_pos:
            label = QGraphicsSimpleTextItem(edge.label)
            label.setFont(QFont("Helvetica", 8))
            p = pt(*edge.label_pos)
            br = label.boundingRect()
            label.setPos(p.x() - br.width() / 2, p.y() - br.height() / 2)
            scene.addItem(label)
    return items


def _path_item(path: QPainterPath, pen: QPen) -> QGraphicsPathItem:
    item = QGraphicsPathItem(path)
    item.setPen(pen)
    return item


def _arrow(before: QPointF, tip: QPointF, color: QColor) -> QGraphicsPolygonItem:
    angle = math.atan2(tip.y() - before.y(), tip.x() - before.x())
    size = 7.0
    left = QPointF(tip.x() - size * math.cos(angle - 0.4), tip.y() - size * math.sin(angle - 0.4))
    right = QPointF(tip.x() - size * math.cos(angle + 0.4), tip.y() - size * math.sin(angle + 0.4))
    item = QGraphicsPolygonItem(QPolygonF([tip, left, right]))
    item.setBrush(QBrush(color))
    item.setPen(QPen(color))
    return item


# --- settings -------------------------------------------------------------------------------------

def _truth(value: Any) -> bool:
    return value is True or str(value).lower() in ("true", "1")


def save_controls(root: QWidget, settings: Any) -> None:
    """Every named control's state into rqt's ``Settings`` (or ``QSettingsAdapter``): line edits,
    check boxes, combo boxes (text), spin boxes, tab widgets, splitters."""
    for w in root.findChildren(QWidget):
        name = w.objectName()
        if not name or name.startswith("qt_") or not _own(root, w):
            continue
        if isinstance(w, QLineEdit):
            settings.set_value(name, w.text())
        elif isinstance(w, QCheckBox) or (isinstance(w, QAbstractButton) and w.isCheckable()):
            settings.set_value(name, w.isChecked())
        elif isinstance(w, QComboBox):
            settings.set_value(name, w.currentText())
        elif isinstance(w, QSpinBox):
            settings.set_value(name, w.value())
        elif isinstance(w, QTabWidget):
            settings.set_value(name, w.currentIndex())
        elif isinstance(w, QSplitter):
            settings.set_value(name, [int(s) for s in w.sizes()])
        elif isinstance(w, QPlainTextEdit) and not w.isReadOnly():
            settings.set_value(name, w.toPlainText())


def restore_controls(root: QWidget, settings: Any) -> None:
    """The reverse of ``save_controls``; keys that are absent leave the control as it is."""
    for w in root.findChildren(QWidget):
        name = w.objectName()
        if not name or name.startswith("qt_") or not _own(root, w):
            continue
        value = settings.value(name, None)
        if value is None:
            continue
        try:
            if isinstance(w, QLineEdit):
                w.setText(str(value))
            elif isinstance(w, QCheckBox) or (isinstance(w, QAbstractButton) and w.isCheckable()):
                w.setChecked(_truth(value))
            elif isinstance(w, QComboBox):
                text = str(value)
                if w.findText(text) < 0 and text:
                    if not w.isEditable():
                        w.addItem(text)
                    else:
                        w.setEditText(text)
                        continue
                w.setCurrentIndex(w.findText(text))
            elif isinstance(w, QSpinBox):
                w.setValue(int(value))
            elif isinstance(w, QTabWidget):
                w.setCurrentIndex(int(value))
            elif isinstance(w, QSplitter):
                sizes = [int(s) for s in (value if isinstance(value, (list, tuple)) else [value])]
                if len(sizes) == w.count():
                    w.setSizes(sizes)
            elif isinstance(w, QPlainTextEdit) and not w.isReadOnly():
                w.setPlainText(str(value))
        except (TypeError, ValueError):
            continue


def _own(root: QWidget, w: QWidget) -> bool:
    """The panel's own controls: not the insides of a combo or spin box, not the cells of a table
    (rows made from a loaded file, which the file restores)."""
    parent = w.parentWidget()
    while parent is not None and parent is not root:
        if isinstance(parent, (QComboBox, QSpinBox, QAbstractItemView)):
            return False
        parent = parent.parentWidget()
    return True


class QSettingsAdapter:
    """rqt's ``Settings`` interface (``value``/``set_value``) over a ``QSettings`` group, for the
    standalone hosts."""

    def __init__(self, qsettings: Any, group: str):
        self.qsettings, self.group = qsettings, group

    def set_value(self, key: str, value: Any) -> None:
        self.qsettings.setValue(f"{self.group}/{key}", value)

    def value(self, key: str, default: Any = None) -> Any:
        return self.qsettings.value(f"{self.group}/{key}", default)

"""The live controller view: where a running ``controller_executor`` is in its automaton.

Attach to an executor by its ``~state`` topic (``ltl_stack/ControllerState``) and the spec it runs:
the automaton is synthesized off the GUI thread with the executor's options and drawn (whole when
small, the neighbourhood of the current state when large); the current state and its goal are
highlighted as ``~state`` moves, input and output lamps follow, the last assumption violation (from
``/diagnostics``) and the mode are shown, and Run/Pause calls ``~set_running``. State ids are those of
``synthesize --dot/--strategy-json`` for the same spec and options. What smach_viewer gives SMACH users.

Messages arrive on rospy's thread and are handed over through ``Latest``; a GUI timer shows the
newest, so the view keeps up with any rate by skipping what it has not had time to draw.
"""
from __future__ import annotations

import gc
import os
import threading
import time
from collections import OrderedDict
from typing import Any

import rospy
from python_qt_binding.QtCore import QSize, Qt, QTimer, Signal
from python_qt_binding.QtWidgets import (
    QCheckBox,
    QFileDialog,
    QFormLayout,
    QGraphicsOpacityEffect,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QListWidget,
    QPlainTextEdit,
    QPushButton,
    QScrollArea,
    QSplitter,
    QVBoxLayout,
    QWidget,
)

from ltl_stack.errors import UserError
from ltl_stack.gui.controller_model import (
    CURRENT_COLOR,
    DEFAULT_FULL_LIMIT,
    DEFAULT_RADIUS,
    GOAL_COLOR,
    ControllerModel,
    ExecutorSource,
    Latest,
    StateUpdate,
    ViewOptions,
    executor_of,
    liveness,
    mode_color,
    mode_text,
    options_from_params,
    resilience_text,
    source_spec,
)
from ltl_stack.gui.dotgraph import sketch_layout
from ltl_stack.gui.widgets import (
    ComboBox,
    GraphView,
    SpinBox,
    Task,
    collector_paused,
    docked_hint,
    restore_controls,
    save_controls,
    show_status,
    status_row,
)
from ltl_stack.gui.worker_process import WorkerProcess, controller_model
from ltl_stack.runtime.executor.options import EFFECTIVE_OPTIONS
from ltl_stack.runtime.executor.running_spec import RunningSpec
from ltl_stack.synthesis.automaton import goal_text

STATE_TYPE = "ltl_stack/ControllerState"
REFRESH_MS = 30
LAYOUT_CACHE = 64  # laid-out neighbourhoods kept
LAMP_ON, LAMP_OFF, LAMP_STALE = "#34c759", "#d0d0d0", "#a8a8a8"
#: how long Attach waits for the executor's latched ~source (what it runs) before using the spec named here
SOURCE_WAIT = 5.0
MASTER_PROBE_PERIOD = 2.0
LIVENESS_PERIOD = 0.5  # seconds between two looks at the executor's liveness
VIOLATION_STATUS = "environment assumptions"  # the executor's /diagnostics status of violations
LEVELS = {0: "OK", 1: "WARN", 2: "ERROR", 3: "STALE"}


def require_master() -> str:
    """The master this process's rospy talks to, if it answers within ``PROBE_TIMEOUT`` seconds; else a
    ``UserError`` (rospy itself would retry for ever). Call it off the GUI thread."""
    from ltl_stack.errors import Exit, UserError
    from ltl_stack.ros.master import PROBE_TIMEOUT, master_online, master_uri

    uri = master_uri(None)
    if not master_online(uri):
        raise UserError(f"no ROS master answers at {uri} (within {PROBE_TIMEOUT:.0f} s); start roscore or the "
                        "scenario, or set ROS_MASTER_URI", Exit.NO_ROS)
    return uri


def ensure_node() -> None:
    """rqt has initialized rospy; a standalone host does it here (anonymous, no signal handlers), once a
    master answers. Off the GUI thread: it talks to the master."""
    if not rospy.core.is_initialized():
        require_master()
        rospy.init_node("ltl_stack_controller_view", anonymous=True, disable_signals=True)


def state_topics() -> list[str]:
    """Topics of type ``ltl_stack/ControllerState`` on the master this process's rospy talks to
    (off the GUI thread: a master that went away is found by ``require_master``'s timeout)."""
    require_master()
    ensure_node()
    return sorted(name for name, type_ in rospy.get_published_topics() if type_ == STATE_TYPE)


def keep_out_of_gc() -> None:
    """Python's full garbage collection walks every object: with spheros' automaton (65,536 states,
    2.1 M edges) that is ~80 ms of GUI thread at unpredictable moments (bench_gui --pictures). The
    automaton lives as long as the view shows it, so it is moved out of the collector's reach (reference
    counting still frees it when it is replaced)."""
    gc.freeze()


def update_of(msg: Any) -> StateUpdate:
    """A ``ControllerState`` message as the view needs it (fields an older executor lacks get defaults)."""
    return StateUpdate(int(msg.state_id), int(msg.goal_index),
                       dict(zip(msg.inputs.keys, msg.inputs.values)),
                       dict(zip(msg.outputs.keys, msg.outputs.values)),
                       bool(msg.running), msg.header.stamp.to_sec(),
                       mode=str(getattr(msg, "mode", "")), violations=int(getattr(msg, "violations", 0)),
                       recovery_steps=int(getattr(msg, "recovery_steps", 0)),
                       unsafe_steps=int(getattr(msg, "unsafe_steps", 0)),
                       resyntheses=int(getattr(msg, "resyntheses", 0)),
                       negotiations=int(getattr(msg, "negotiations", 0)),
                       negotiated=int(getattr(msg, "resyntheses_negotiated", 0)),
                       violated_clauses=tuple(getattr(msg, "violated_clauses", ())),
                       spec_file=str(getattr(msg, "spec_file", "")),
                       generation=int(getattr(msg, "strategy_generation", 0)))


def source_of(msg: Any) -> ExecutorSource:
    """A ``ControllerSource`` message (``~source``) as the view needs it."""
    return ExecutorSource(RunningSpec(
        spec_file=str(msg.spec_file), spec_sha256=str(msg.spec_sha256), spec_text=str(msg.spec_text),
        strategy_file=str(msg.strategy_file), generation=int(msg.strategy_generation),
        robotics_semantics=bool(msg.robotics_semantics), cooperative=bool(msg.cooperative),
        max_explicit_states=int(msg.max_explicit_states)), msg.started.to_sec())


class RosLink:
    """Subscribers of one executor's ``~state``, ``~source`` and of ``/diagnostics``, its ``~set_running``,
    and what tells whether it is alive: the time of its last message (``heard``; its statuses come every
    second), whether its ``~state`` publisher is connected and whether the master answers (asked every
    ``MASTER_PROBE_PERIOD`` seconds on a thread of its own)."""

    def __init__(self, state_topic: str, on_state, on_diagnostic):
        from diagnostic_msgs.msg import DiagnosticArray

        from ltl_stack.msg import ControllerSource, ControllerState
        from ltl_stack.ros.master import master_uri

        require_master()
        ensure_node()
        self.state_topic = state_topic
        self.executor = executor_of(state_topic)
        self._on_diagnostic = on_diagnostic
        self.created = self.heard = time.monotonic()
        self.state_heard: float | None = None
        self.master_ok = True
        self.source = Latest()  # the newest ~source (ExecutorSource)
        self._source_came = threading.Event()
        self._closed = threading.Event()
        self._uri = master_uri(None)

        def state(msg: Any) -> None:
            self.heard = self.state_heard = time.monotonic()
            on_state(update_of(msg))
        self.state_sub = rospy.Subscriber(state_topic, ControllerState, state, queue_size=1000, tcp_nodelay=True)
        self.source_sub = rospy.Subscriber(f"{self.executor}/source", ControllerSource, self._source, queue_size=10)
        self.diag_sub = rospy.Subscriber("/diagnostics", DiagnosticArray, self._diagnostics, queue_size=100)
        threading.Thread(target=self._probe_master, name="ltl_stack_gui_master_probe", daemon=True).start()

    def _source(self, msg: Any) -> None:
        self.heard = time.monotonic()
        self.source.put(source_of(msg))
        self._source_came.set()

    def wait_source(self, timeout: float) -> ExecutorSource | None:
        """The executor's ``~source`` (latched), waiting up to ``timeout`` s; None from an executor that
        does not publish one."""
        self._source_came.wait(timeout)
        return self.source.peek()

    def _probe_master(self) -> None:
        from ltl_stack.ros.master import master_online

        while not self._closed.wait(MASTER_PROBE_PERIOD):
            self.master_ok = master_online(self._uri)

    def alive(self) -> tuple[bool, str]:
        """(alive, text) as ``controller_model.liveness`` tells."""
        return liveness(time.monotonic(), self.heard, self.state_heard, self.state_sub.get_num_connections() > 0,
                        self.master_ok, self.created)

    def _diagnostics(self, msg: Any) -> None:
        prefix = f"{self.executor}: "
        for status in msg.status:
            if status.hardware_id != self.executor:
                continue
            self.heard = time.monotonic()
            level = int(ord(status.level) if isinstance(status.level, bytes) else status.level)
            what = status.name[len(prefix):] if status.name.startswith(prefix) else status.name
            self._on_diagnostic(level, status.message, what)

    def params(self) -> dict[str, object]:
        """The options the executor runs with (its ``~effective_options``, defaults filled in); from an
        executor that does not publish them, its private parameters that change the synthesis."""
        effective = rospy.get_param(f"{self.executor}/{EFFECTIVE_OPTIONS}", None)
        if isinstance(effective, dict):
            return effective
        found = {}
        for name in ("robotics_semantics", "cooperative"):
            key = f"{self.executor}/{name}"
            if rospy.has_param(key):
                found[name] = rospy.get_param(key)
        return found

    def set_running(self, running: bool, timeout: float = 10.0) -> str:
        from std_srvs.srv import SetBool

        service = f"{self.executor}/set_running"
        rospy.wait_for_service(service, timeout)
        reply = rospy.ServiceProxy(service, SetBool)(running)
        return reply.message

    def close(self) -> None:
        self._closed.set()
        self.state_sub.unregister()
        self.source_sub.unregister()
        self.diag_sub.unregister()


class ControllerView(QWidget):
    """The view; ``model`` is the attached automaton, ``shown`` the last update drawn."""

    diagnostic = Signal(int, str, str)  # level, message, the status' concern ("mode", "environment assumptions", …)

    def __init__(self, parent: QWidget | None = None, link_factory=RosLink, list_topics=state_topics):
        super().__init__(parent)
        self.setObjectName("ControllerView")
        self.setWindowTitle("Controller view")
        self.model: ControllerModel | None = None
        self.link: RosLink | None = None
        self.latest = Latest()
        self.shown: StateUpdate | None = None
        self.shown_count = 0
        self.lag: list[float] = []  # seconds from a message's stamp to its display, while recording
        self.record_lag = False
        self.violation = ""
        self.statuses: dict[str, tuple[int, str]] = {}  # the executor's /diagnostics: concern -> (level, message)
        self.alive = True  # the attached executor is heard from (``controller_model.liveness``)
        self._liveness_at = 0.0
        self._pending_source: ExecutorSource | None = None
        self.task: Task | None = None
        self.refresh_task: Task | None = None
        self.reload_task: Task | None = None
        self.layout_task: Task | None = None
        #: the process the syntheses run in (no GIL shared with the GUI; None: on a worker thread here)
        self.worker: WorkerProcess | None = WorkerProcess()
        self.layout_count = 0  # Graphviz runs (a neighbourhood seen before is drawn from the cache)
        self.sketch_count = 0  # neighbourhoods sketched while Graphviz lays them out
        self.sketching = True  # off: a state that left the picture waits for Graphviz (bench_gui's peer)
        self._layouts: OrderedDict[tuple, tuple] = OrderedDict()
        self._failed_layout: tuple | None = None
        self._drawn: set[int] = set()
        self._link_factory = link_factory
        self._list_topics = list_topics
        self._lamps: dict[tuple[str, str], QLabel] = {}
        self._build()
        self.diagnostic.connect(self._on_diagnostic)
        self.timer = QTimer(self)
        self.timer.timeout.connect(self.tick)
        self.timer.start(REFRESH_MS)

    # --- layout ---------------------------------------------------------------------------------------
    def _build(self) -> None:
        grid = QGridLayout()
        self.spec_line_edit = QLineEdit()
        self.spec_line_edit.setObjectName("spec_line_edit")
        self.spec_line_edit.setPlaceholderText("the spec the executor runs")
        browse = QPushButton("Browse…")
        browse.setObjectName("spec_browse_push_button")
        browse.clicked.connect(self._browse)
        self.topic_combo_box = ComboBox()
        self.topic_combo_box.setObjectName("state_topic_combo_box")
        self.topic_combo_box.setEditable(True)
        self.topic_combo_box.setMinimumWidth(220)
        self.topic_combo_box.lineEdit().setPlaceholderText("/<ns>/controller_executor/state")
        self.refresh_push_button = QPushButton("Refresh")
        self.refresh_push_button.setObjectName("refresh_topics_push_button")
        self.refresh_push_button.clicked.connect(self.refresh_topics)
        self.robotics_check_box = QCheckBox("Robotics semantics")
        self.robotics_check_box.setObjectName("robotics_semantics_check_box")
        self.robotics_check_box.setChecked(True)
        self.cooperative_check_box = QCheckBox("Cooperative")
        self.cooperative_check_box.setObjectName("cooperative_check_box")
        self.cooperative_check_box.setChecked(True)
        self.full_spin_box = SpinBox()
        self.full_spin_box.setObjectName("full_limit_spin_box")
        self.full_spin_box.setRange(1, 100_000)
        self.full_spin_box.setValue(DEFAULT_FULL_LIMIT)
        self.full_spin_box.setToolTip("draw the whole automaton up to this many states, else a neighbourhood")
        self.radius_spin_box = SpinBox()
        self.radius_spin_box.setObjectName("radius_spin_box")
        self.radius_spin_box.setRange(1, 20)
        self.radius_spin_box.setValue(DEFAULT_RADIUS)
        self.attach_push_button = QPushButton("Attach")
        self.attach_push_button.setObjectName("attach_push_button")
        self.attach_push_button.clicked.connect(self.attach)
        self.cancel_push_button = QPushButton("Cancel")
        self.cancel_push_button.setObjectName("cancel_push_button")
        self.cancel_push_button.setToolTip("stop attaching: the synthesis stops at its next step, the topic is let go")
        self.cancel_push_button.clicked.connect(self.cancel)
        self.cancel_push_button.hide()
        grid.addWidget(QLabel("Spec"), 0, 0)
        grid.addWidget(self.spec_line_edit, 0, 1, 1, 4)
        grid.addWidget(browse, 0, 5)
        grid.addWidget(QLabel("State topic"), 1, 0)
        grid.addWidget(self.topic_combo_box, 1, 1, 1, 4)
        grid.addWidget(self.refresh_push_button, 1, 5)
        # two rows, so that two panels docked side by side fit a 1280 px screen
        options = QHBoxLayout()
        options.addWidget(self.robotics_check_box)
        options.addWidget(self.cooperative_check_box)
        options.addStretch(1)
        options.addWidget(self.attach_push_button)
        options.addWidget(self.cancel_push_button)
        grid.addLayout(options, 2, 0, 1, 6)
        sizes = QHBoxLayout()
        sizes.addWidget(QLabel("whole graph up to"))
        sizes.addWidget(self.full_spin_box)
        sizes.addWidget(QLabel("states, else radius"))
        sizes.addWidget(self.radius_spin_box)
        sizes.addStretch(1)
        grid.addLayout(sizes, 3, 0, 1, 6)

        self.graph_view = GraphView()
        self.graph_view.setObjectName("automaton_graphics_view")
        side = QWidget()
        side_layout = QVBoxLayout(side)
        side_layout.setContentsMargins(0, 0, 0, 0)
        self.state_label = QLabel("state: —")
        self.state_label.setObjectName("state_label")
        self.state_label.setStyleSheet("font-size: 15px; font-weight: bold;")
        self.liveness_label = QLabel("")
        self.liveness_label.setObjectName("liveness_label")
        self.liveness_label.setWordWrap(True)
        self.liveness_label.setToolTip("when the executor last published its state; the picture, lamps and Pause "
                                       "are greyed while the executor is not heard from (no publisher, no master, "
                                       "or no message for a few seconds)")
        self.mode_label = QLabel("mode: not attached")
        self.mode_label.setObjectName("mode_label")
        self.mode_label.setWordWrap(True)
        self.run_pause_push_button = QPushButton("Pause")
        self.run_pause_push_button.setObjectName("run_pause_push_button")
        self.run_pause_push_button.setEnabled(False)
        self.run_pause_push_button.clicked.connect(self.toggle_running)
        self.inputs_box = QGroupBox("Inputs")
        self.outputs_box = QGroupBox("Outputs")
        QFormLayout(self.inputs_box)
        QFormLayout(self.outputs_box)
        self.violation_text = QPlainTextEdit()
        self.violation_text.setObjectName("violation_plain_text_edit")
        self.violation_text.setReadOnly(True)
        self.violation_text.setPlaceholderText("no environment-assumption violation reported")
        self.violation_text.setMaximumHeight(90)
        self.resilience_label = QLabel("")
        self.resilience_label.setObjectName("resilience_label")
        self.resilience_label.setWordWrap(True)
        self.resilience_label.setToolTip("the executor's counters (thesis ch. 4): violating transitions, recovery "
                                         "steps, steps without a safe move, strategies put in place since start-up")
        self.strategy_label = QLabel("")
        self.strategy_label.setObjectName("strategy_label")
        self.strategy_label.setWordWrap(True)
        self.violated_list_widget = QListWidget()
        self.violated_list_widget.setObjectName("violated_clauses_list_widget")
        self.violated_list_widget.setToolTip("environment-safety clauses the current inputs violate (file:line: "
                                             "text (in words)), as the executor reports them on ~state")
        self.violated_list_widget.setMaximumHeight(90)
        side_layout.addWidget(self.state_label)
        side_layout.addWidget(self.liveness_label)
        side_layout.addWidget(self.mode_label)
        side_layout.addWidget(self.resilience_label)
        side_layout.addWidget(self.strategy_label)
        side_layout.addWidget(self.run_pause_push_button)
        lamps = QHBoxLayout()
        lamps.addWidget(self.inputs_box)
        lamps.addWidget(self.outputs_box)
        side_layout.addLayout(lamps)
        side_layout.addWidget(QLabel("Violated clauses now"))
        side_layout.addWidget(self.violated_list_widget)
        side_layout.addWidget(QLabel("Last violation (diagnostics)"))
        side_layout.addWidget(self.violation_text)
        side_layout.addStretch(1)
        middle = QSplitter(Qt.Horizontal)
        middle.setObjectName("view_splitter")
        middle.addWidget(self.graph_view)
        scroll = QScrollArea()  # the lamps of a large spec scroll; they never make the window taller
        scroll.setWidgetResizable(True)
        scroll.setFrameShape(QScrollArea.NoFrame)
        scroll.setWidget(side)
        middle.addWidget(scroll)
        middle.setStretchFactor(0, 4)
        middle.setStretchFactor(1, 1)
        middle.setSizes([1000, 380])

        bottom, self.progress_bar, self.status_label = status_row("Name the spec and the executor's state topic, then Attach.")
        self.banner_label = QLabel("")
        self.banner_label.setObjectName("source_banner_label")
        self.banner_label.setWordWrap(True)
        self.banner_label.setStyleSheet("color: white; background: #c00000; padding: 4px; font-weight: bold;")
        self.banner_label.hide()
        self.graph_opacity = QGraphicsOpacityEffect(self.graph_view)
        self.graph_opacity.setOpacity(1.0)
        self.graph_view.setGraphicsEffect(self.graph_opacity)
        layout = QVBoxLayout(self)
        layout.addLayout(grid)
        layout.addWidget(self.banner_label)
        layout.addWidget(middle, 1)
        layout.addLayout(bottom)

    def _browse(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Spec", self.spec_line_edit.text() or os.getcwd())
        if path:
            self.spec_line_edit.setText(path)

    def _fill_lamps(self) -> None:
        self._lamps = {}
        for box, names in ((self.inputs_box, self.model.automaton.inputs),
                           (self.outputs_box, self.model.automaton.outputs)):
            form = box.layout()
            while form.rowCount():
                form.removeRow(0)
            for name in names:
                lamp = QLabel()
                lamp.setObjectName(f"{name}_lamp_label")
                lamp.setFixedSize(14, 14)
                form.addRow(lamp, QLabel(name))
                self._lamps[(box.title(), name)] = lamp
        self._set_lamps()

    # --- attaching ------------------------------------------------------------------------------------
    def refresh_topics(self) -> bool:
        """List the executors' state topics off the GUI thread; False while a listing is under way."""
        if self.refresh_task is not None and self.refresh_task.running:
            return False
        self.refresh_task = Task(lambda _p: self._list_topics(), self)
        self.refresh_task.finished.connect(lambda topics: (self.refresh_push_button.setEnabled(True),
                                                          self._on_topics(topics)))
        self.refresh_task.failed.connect(lambda text: (self.refresh_push_button.setEnabled(True), self._status(
            f"Cannot list the state topics: {text}", error=True)))
        self.refresh_push_button.setEnabled(False)
        self._status("Asking the master for executor state topics…")
        self.refresh_task.start()
        return True

    def _on_topics(self, topics: list[str]) -> None:
        current = self.topic_combo_box.currentText()
        self.topic_combo_box.clear()
        self.topic_combo_box.addItems(topics)
        if current:
            self.topic_combo_box.setEditText(current)
        elif topics:
            self.topic_combo_box.setCurrentIndex(0)
        self._status(f"{len(topics)} executor state topic(s) on the master.")

    def options(self) -> ViewOptions:
        return ViewOptions(self.robotics_check_box.isChecked(), self.cooperative_check_box.isChecked(),
                           self.full_spin_box.value(), self.radius_spin_box.value())

    def attach(self) -> bool:
        """Subscribe to the state topic, learn what the executor runs (its latched ``~source``: spec,
        generation, options; else the spec named here and its parameters), synthesize off the GUI thread.
        Whatever was shown of an earlier executor is cleared first."""
        if self.task is not None and self.task.running:
            return False
        spec, topic = self.spec_line_edit.text().strip(), self.topic_combo_box.currentText().strip()
        if not topic:
            self._status("Name the executor's state topic (and, for an executor that does not say what it runs, "
                         "its spec).", error=True)
            return False
        self.detach()
        self._clear()
        wanted = self.options()
        factory, latest, worker = self._link_factory, self.latest, self.worker
        diagnose = self._diagnose

        def work(progress):  # every master call here, off the GUI thread
            progress(f"connecting to {topic}")
            link = factory(topic, latest.put, diagnose)
            try:
                source = link.wait_source(SOURCE_WAIT) if hasattr(link, "wait_source") else None
                if source is not None:
                    path, warning = source_spec(source, spec)
                    if path is None:
                        raise UserError(warning)
                    options = source.options(wanted)
                else:
                    if not spec:
                        raise UserError(f"{executor_of(topic)} does not say what it runs (no ~source): name its spec")
                    path, warning, options = spec, "", options_from_params(link.params(), wanted)
                model = controller_model(worker, path, options, progress)
                model.source = source
                if source is not None:
                    model.generation = source.spec.generation
                progress(f"attached to {topic}")  # raises Cancelled when Cancel came meanwhile
                return link, model, warning
            except BaseException:
                link.close()
                raise

        def discard(done: tuple) -> None:  # Cancel came after the last progress report
            threading.Thread(target=done[0].close, name="ltl_stack_gui_detach", daemon=True).start()
        # assembling 65,536 states made full collections that held the GIL ~400 ms (bench_gui --pictures)
        self.task = Task(collector_paused(work), self, discard=discard)
        self.task.progress.connect(self._status)
        self.task.finished.connect(self._on_attached)
        self.task.failed.connect(lambda text: (self._busy(False), self._clear(),
                                               self._status(f"Cannot attach: {text}", error=True)))
        self._busy(True)
        self._status(f"Attaching to {topic}…")
        self.task.start()
        return True

    def cancel(self) -> bool:
        """Stop attaching: the synthesis stops at its next progress report and the topic is let go."""
        if self.task is None or not self.task.running:
            return False
        self.task.abandon()
        if self.worker is not None:
            self.worker.kill()
        self._busy(False)
        self._clear()
        self._status("Cancelled: not attached.")
        return True

    def detach(self) -> None:
        if self.link is not None:  # unregistering talks to the master: not on the GUI thread
            threading.Thread(target=self.link.close, name="ltl_stack_gui_detach", daemon=True).start()
            self.link = None
        self.model, self.shown, self._drawn = None, None, set()
        self._pending_source = None

    def _clear(self) -> None:
        """Forget what was shown of an executor: picture, state, mode, lamps, counters, strategy, violations."""
        self.shown, self.violation, self.statuses = None, "", {}
        self.latest.take()
        self.graph_view.show_message("")
        self._drawn = set()
        self.state_label.setText("state: —")
        self.liveness_label.setText("")
        self.resilience_label.setText("")
        self.strategy_label.setText("")
        self.strategy_label.setStyleSheet("")
        self.violated_list_widget.clear()
        self.violation_text.setPlainText("")
        self.banner_label.hide()
        self.banner_label.setText("")
        self.run_pause_push_button.setEnabled(False)
        self.run_pause_push_button.setText("Pause")
        for box in (self.inputs_box, self.outputs_box):
            form = box.layout()
            while form.rowCount():
                form.removeRow(0)
        self._lamps = {}
        self._set_alive(True)
        self.mode_label.setText("mode: not attached")
        self.mode_label.setStyleSheet("")

    def _banner(self, text: str) -> None:
        self.banner_label.setText(text)
        self.banner_label.setVisible(bool(text))

    def _on_attached(self, done: tuple) -> None:
        self.link, model, warning = done
        self._banner(warning)
        self._on_model(model)

    def _on_model(self, model: ControllerModel) -> None:
        self._busy(False)
        self.model = model
        keep_out_of_gc()
        self._drawn = set()
        self.robotics_check_box.setChecked(model.options.robotics_semantics)
        self.cooperative_check_box.setChecked(model.options.cooperative)
        self._fill_lamps()
        self.run_pause_push_button.setEnabled(self.alive)
        how = "whole" if model.whole else f"neighbourhood of the current state (radius {model.options.radius})"
        whose = "the executor's spec" if model.source is not None else "the spec named here"
        self._status(f"{model.spec_path} ({whose}): {len(model.automaton)} states, {model.automaton.goals} goals; "
                     f"drawing the {how}. Ids as in synthesize --dot/--strategy-json (robotics semantics "
                     f"{model.options.robotics_semantics}, cooperative {model.options.cooperative}).")
        if model.generation:
            self.strategy_label.setText(f"strategy {model.generation}: {model.spec_path} ({len(model.automaton)} states)")
            self.strategy_label.setStyleSheet("")
        self.shown = None
        self._relayout(None)  # the latched state that arrived meanwhile is still in ``latest``

    # --- following --------------------------------------------------------------------------------------
    def tick(self) -> None:
        """Show the newest state (GUI timer); everything older that arrived meanwhile is skipped. Follow
        what the executor says it runs (a restart, a new strategy) and show whether it is alive."""
        if self.link is None:
            return
        now = time.monotonic()
        if now - self._liveness_at >= LIVENESS_PERIOD:
            self._liveness_at = now
            self._show_liveness()
        self._follow_source()
        if self.model is None:
            return
        update = self.latest.take()
        if update is None:
            return
        self.show_update(update)

    def _follow_source(self) -> None:
        """A ``~source`` other than the drawn one (the executor restarted, perhaps with another spec, or
        put a new strategy in place): stop placing states in the old automaton and load the new one."""
        source = getattr(self.link, "source", None)
        fresh = source.take() if source is not None else None
        if fresh is not None:
            self._pending_source = fresh
        pending = self._pending_source
        if pending is None or (self.reload_task is not None and self.reload_task.running):
            return
        self._pending_source = None
        drawn = self.model.source if self.model is not None else None
        if drawn is not None and drawn.key == pending.key:
            return
        restarted = drawn is not None and drawn.started != pending.started
        self._load_source(pending, restarted)

    def _load_source(self, source: ExecutorSource, restarted: bool) -> None:
        named = self.spec_line_edit.text().strip()
        options = source.options(self.options())
        worker, link = self.worker, self.link
        what = "restarted" if restarted else f"runs strategy {source.spec.generation}"

        def work(progress):
            path, warning = source_spec(source, named)
            if path is None:
                raise UserError(warning)
            model = controller_model(worker, path, options, progress)
            model.source, model.generation = source, source.spec.generation
            return model, warning

        def loaded(done: tuple) -> None:
            if self.link is not link:
                return  # detached or attached elsewhere meanwhile
            model, warning = done
            self._banner(warning)
            self._on_model(model)

        def failed(text: str) -> None:
            if self.link is link:
                self._banner(f"The executor {what}; cannot draw it: {text}")
        # the old automaton is not the running one any more: nothing is placed in it meanwhile; the last
        # state is placed in the new one unless a newer one comes
        if self.shown is not None and self.latest.peek() is self.shown:
            self.latest.put(self.shown)
        self.model, self.shown, self._drawn = None, None, set()
        self.graph_view.show_message(f"the executor {what}: loading {source.spec.spec_file}…")
        self.state_label.setText("state: —")
        self.strategy_label.setText(f"strategy {source.spec.generation}: loading {source.spec.spec_file}…"
                                    if source.spec.generation else "")
        self.strategy_label.setStyleSheet("")
        self._status(f"The executor {what}: loading {source.spec.spec_file or 'its spec'}…")
        self.reload_task = Task(collector_paused(work), self)
        self.reload_task.finished.connect(loaded)
        self.reload_task.failed.connect(failed)
        self.reload_task.start()

    def _show_liveness(self) -> None:
        alive_of = getattr(self.link, "alive", None)
        if alive_of is None:
            return
        alive, text = alive_of()
        if self.liveness_label.text() != text:
            self.liveness_label.setText(text)
        if alive != self.alive:
            self._set_alive(alive)

    def _set_alive(self, alive: bool) -> None:
        """Grey the picture and the lamps and disable Pause while the executor is not heard from."""
        self.alive = alive
        self.graph_opacity.setOpacity(1.0 if alive else 0.3)
        self.liveness_label.setStyleSheet("" if alive else "color: white; background: #707070; padding: 2px;")
        self.run_pause_push_button.setEnabled(alive and self.model is not None)
        for lamp in self._lamps.values():
            lamp.setProperty("lit", None)  # repainted by _set_lamps
        self._set_lamps()
        self._show_mode(self.shown)

    def show_update(self, update: StateUpdate) -> None:
        model = self.model
        drawn = model.source.spec if model.source is not None else None
        if drawn is not None and update.spec_file and (update.spec_file, update.generation) != (
                drawn.spec_file, drawn.generation):
            # a state of another strategy (a restarted executor, a new generation) before its ~source: it is
            # not placed in this automaton
            model.current = None
            self.shown = update
            self.state_label.setText(f"state: of {update.spec_file} (strategy {update.generation}), not drawn yet")
            self._mark()
            return
        current = model.follow(update)
        self.shown = update
        self.shown_count += 1
        if self.record_lag and update.stamp:
            self.lag.append(time.time() - update.stamp)
        if current is None:
            text = "not started" if update.state_id < 0 else \
                f"not in the automaton (executor's id {update.state_id})"
            self.state_label.setText(f"state: {text}")
        else:
            self.state_label.setText(f"state {current} (goal {goal_text(update.goal, model.automaton.goals)})")
        self._show_mode(update)
        self.resilience_label.setText(resilience_text(update))
        clauses = list(update.violated_clauses)
        if clauses != [self.violated_list_widget.item(i).text() for i in range(self.violated_list_widget.count())]:
            self.violated_list_widget.clear()
            self.violated_list_widget.addItems(clauses)
        self.run_pause_push_button.setText("Pause" if update.running else "Run")
        self._set_lamps()
        if update.generation != model.generation and model.source is None:
            self._reload(update)  # an executor without ~source: its ~state names the new spec
        if model.needs_new_layout(self._drawn, current):
            self._relayout(current)
        else:
            self._mark()

    def _show_mode(self, update: StateUpdate | None) -> None:
        text = "mode: " + mode_text(update, self.violation, self.statuses)
        color = mode_color(update)
        if not self.alive and self.link is not None:
            text, color = f"{text} (as last heard: the executor is not heard from)", "#707070"
        self.mode_label.setText(text)
        style = f"color: white; background: {color}; padding: 2px;" if color else ""
        if self.mode_label.styleSheet() != style:  # setting it re-polishes the label, even when the same
            self.mode_label.setStyleSheet(style)

    def _reload(self, update: StateUpdate) -> None:
        """The executor put a new strategy in place (resynthesis or adoption): load its spec, as the
        executor reports it, off the GUI thread; meanwhile states are placed in the old automaton."""
        model = self.model
        if self.reload_task is not None and self.reload_task.running:
            return
        model.generation = update.generation  # asked once per generation, whatever the outcome
        if not update.spec_file:
            self.strategy_label.setText(f"strategy {update.generation}: not written to a file (start the executor "
                                        "with --characterized-spec): the picture is of an older strategy")
            self.strategy_label.setStyleSheet("color: #a00000;")
            return
        spec, options, generation, worker = update.spec_file, model.options, update.generation, self.worker

        def work(progress):
            new = controller_model(worker, spec, options, progress)
            new.generation = generation
            return new
        self.reload_task = Task(collector_paused(work), self)
        self.reload_task.finished.connect(self._on_reloaded)
        self.reload_task.failed.connect(lambda text: (self.strategy_label.setText(
            f"strategy {generation}: cannot load {spec}: {text}"), self.strategy_label.setStyleSheet("color: #a00000;")))
        self.strategy_label.setText(f"strategy {generation}: loading {spec}…")
        self.strategy_label.setStyleSheet("")
        self.reload_task.start()

    def _on_reloaded(self, model: ControllerModel) -> None:
        if self.model is None:
            return  # detached meanwhile
        self.model = model
        keep_out_of_gc()
        self._drawn = set()
        self._fill_lamps()
        self.strategy_label.setText(f"strategy {model.generation}: {model.spec_path} ({len(model.automaton)} states)")
        self.strategy_label.setStyleSheet("")
        if self.shown is not None:
            self.show_update(self.shown)
        else:
            self._relayout(None)

    def current_node_id(self) -> str | None:
        """The graph's node id of the highlighted state (None when it is not drawn)."""
        graph = self.graph_view.graph
        if graph is None or self.model is None or self.model.current is None:
            return None
        return graph.key.get(self.model.current)

    def _mark(self) -> None:
        graph = self.graph_view.graph
        if graph is None or self.model is None:
            return
        marks = {}
        current = self.model.current
        if current is not None and current in graph.key:
            marks[graph.key[current]] = CURRENT_COLOR
            for t in self.model.automaton.states[current].successors:  # where it can go next
                if t in graph.key and t != current:
                    marks.setdefault(graph.key[t], GOAL_COLOR)
        self.graph_view.highlight(marks)
        if current is not None and current in graph.key:
            self.graph_view.center_on_node(graph.key[current])

    def _relayout(self, center: int | None) -> None:
        """Draw the neighbourhood of ``center`` (the whole graph when small): from the cache of laid-out
        neighbourhoods, else built and laid out off the GUI thread; one layout at a time, the newest
        centre wins. A failed layout is tried again only for another centre. Meanwhile a state that
        left the picture is shown at once in a sketch of its neighbourhood (``sketch_layout``)."""
        model = self.model
        key = (id(model), None if model.whole else center)
        cached = self._layouts.get(key)
        if cached is not None:
            self._layouts.move_to_end(key)
            self._on_layout((key, *cached))
            return
        graph = None
        if self.sketching and center is not None and center not in self._drawn and not model.whole:
            graph = model.graph(center)
            self.graph_view.draw(graph, sketch_layout(graph, graph.key[center]))
            self._drawn = set(k for k in graph.key if isinstance(k, int))
            self._mark()
            self.sketch_count += 1
        if (self.layout_task is not None and self.layout_task.running) or key == self._failed_layout:
            return
        view = self.graph_view

        def work(_progress):
            laid = graph if graph is not None else model.graph(center)
            return key, laid, view.layout_for(laid)
        self.layout_count += 1
        self.layout_task = Task(work, self)
        self.layout_task.finished.connect(self._on_layout)
        self.layout_task.failed.connect(lambda text: (setattr(self, "_failed_layout", key), view.show_message(
            f"{text}\n(tried again when the state moves on)")))
        self.layout_task.start()

    def _on_layout(self, done: tuple) -> None:
        key, graph, laid_out = done
        self._layouts[key] = (graph, laid_out)
        while len(self._layouts) > LAYOUT_CACHE:
            self._layouts.popitem(last=False)
        if self.model is None or key[0] != id(self.model):
            return
        current = self.model.current
        if current is not None and current in self._drawn and current not in graph.key:
            self._relayout(current)  # the state moved on meanwhile: its sketch stays until its own layout
            return
        self.graph_view.draw(graph, laid_out)
        self._drawn = set(k for k in graph.key if isinstance(k, int))
        self._mark()
        if self.model.current is not None and self.model.needs_new_layout(self._drawn, self.model.current):
            self._relayout(self.model.current)

    def _set_lamps(self) -> None:
        if self.model is None:
            return
        ins, outs = self.model.lamps(self.shown)
        for title, pairs in (("Inputs", ins), ("Outputs", outs)):
            for name, value in pairs:
                lamp = self._lamps.get((title, name))
                lit = bool(value) if self.alive else "stale"
                if lamp is not None and lamp.property("lit") != lit:  # a style sheet costs a re-polish
                    lamp.setProperty("lit", lit)
                    color = LAMP_STALE if not self.alive else LAMP_ON if value else LAMP_OFF
                    lamp.setStyleSheet(f"background: {color}; border-radius: 7px;")
                    lamp.setToolTip(f"{name}: {'true' if value else 'false'}"
                                    + ("" if self.alive else " (last heard; the executor is not heard from)"))

    def lamp_values(self) -> dict[str, bool]:
        """What the lamps show (for tests): name -> lit."""
        return {name: LAMP_ON in lamp.styleSheet() for (_t, name), lamp in self._lamps.items()}

    def _diagnose(self, level: int, message: str, what: str = VIOLATION_STATUS) -> None:
        """The ROS link's diagnostics callback (any thread): one status of the executor."""
        self.diagnostic.emit(int(level), str(message), str(what))

    def _on_diagnostic(self, level: int, message: str, what: str = VIOLATION_STATUS) -> None:
        """One /diagnostics status of the attached executor: kept for the status texts; a violation, at
        any level (a recovered one is a WARN), is shown until the next one, with "cleared" when the
        inputs are admissible again."""
        known = self.statuses.get(what)
        self.statuses[what] = (level, message)
        if what == VIOLATION_STATUS:
            if level >= 1:
                if message != self.violation:
                    self.violation = message
                    self.violation_text.setPlainText(f"[{LEVELS.get(level, level)}] {message}")
            elif self.violation:
                self.violation = ""
                self.violation_text.setPlainText(self.violation_text.toPlainText() + f"\n(cleared: {message})")
        if known != (level, message):
            self._show_mode(self.shown)

    # --- run / pause ------------------------------------------------------------------------------------
    def toggle_running(self) -> None:
        if self.link is None or not self.alive:
            return
        running = not (self.shown.running if self.shown is not None else True)
        link = self.link
        task = Task(lambda _p: link.set_running(running), self)
        task.finished.connect(lambda message: self._status(f"{'Run' if running else 'Pause'}: {message or 'done'}"))
        task.failed.connect(lambda text: self._status(f"set_running failed: {text}", error=True))
        self._service_task = task
        task.start()

    # --- plumbing -----------------------------------------------------------------------------------------
    def _busy(self, busy: bool) -> None:
        self.progress_bar.setVisible(busy)
        self.cancel_push_button.setVisible(busy)
        self.attach_push_button.setEnabled(not busy)

    def _status(self, text: str, error: bool = False) -> None:
        show_status(self.status_label, text, error)

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt's name
        return docked_hint(super().sizeHint())

    def save_settings(self, settings: Any) -> None:
        save_controls(self, settings)

    def restore_settings(self, settings: Any) -> None:
        """The saved fields, then Attach again when they name a topic (a restored perspective
        shows the executor it showed; attaching is off the GUI thread and says so when there is no master)."""
        restore_controls(self, settings)
        if self.topic_combo_box.currentText().strip():
            self.attach()

    def shutdown(self) -> None:
        self.timer.stop()
        self.detach()
        if self.worker is not None:
            self.worker.close()

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt's name
        self.shutdown()
        super().closeEvent(event)

"""Long work of the panels in a process of its own: the analysis panel's analyses and the controller
view's syntheses. Qt-free.

A worker thread running Python code stalls the GUI thread: every event PyQt hands to Python waits for
the GIL, and on a loaded machine the worker is often descheduled while it holds it (bench_gui
--pictures: 61 ms stalls during an analysis with the GIL handed over every 0.2 ms and six busy
processes beside it), and a synthesis' CUDD calls hold the GIL for as long as each runs. In a process
of its own the work shares no GIL with the GUI. It
sends its result in small parts that the panel's worker thread reads one by one, each read short (the
analysis of a 10,000-node graph is 7.7 MB pickled, 280 ms to read in one call). Cancel kills the
process: the work really stops.

Protocol on the child's stdin/stdout, one pickle per message. Request: ``(job, arguments)`` with job
``"analysis"`` (``analyze_request``'s dict) or ``"automaton"`` (``{"spec": path, "options": ViewOptions}``).
Replies: ``("progress", text)``, then the parts and ``("done",)``, or ``("error", text, code)``. The
child ends when its stdin closes (the panel closed, or its process ended).
"""
from __future__ import annotations

import gc
import os
import pickle
import subprocess
import sys
import threading
import traceback
import weakref
from collections.abc import Callable, Iterable, Iterator
from typing import Any, BinaryIO

from ltl_stack.errors import Exit, UserError
from ltl_stack.gui.analysis_model import AnalysisResult, AnalysisView, run_analysis
from ltl_stack.gui.controller_model import ControllerModel, automaton_parts, synthesize_automaton


def analyze_request(request: dict[str, Any], progress: Callable[[str], None]) -> AnalysisResult:
    """One analysis request, analysed in this process."""
    return run_analysis(request["spec"], request["mapping"], snapshot=request.get("snapshot"),
                        snapshot_path=request.get("snapshot_path"), robots=request.get("robots", ()),
                        ignore_topics=request.get("ignore_topics", ()), progress=progress)


#: job -> what the child sends for it (the parts, from its arguments and a progress callback)
JOBS: dict[str, Callable[[Any, Callable[[str], None]], Iterable[tuple]]] = {
    "analysis": lambda request, progress: analyze_request(request, progress).parts(),
    "automaton": lambda request, progress: automaton_parts(
        synthesize_automaton(request["spec"], request["options"], progress)),
}


class WorkFailed(UserError):
    """The work in the child process failed; the message is what the panel shows."""


class WorkerProcess:
    """One child process for a panel's long work, reused from one job to the next (it starts once)."""

    def __init__(self) -> None:
        self._proc: subprocess.Popen | None = None
        self._lock = threading.Lock()
        self._finalizer: weakref.finalize | None = None

    def _start(self) -> subprocess.Popen:
        if self._proc is None or self._proc.poll() is not None:
            self._proc = subprocess.Popen(child_command(), stdin=subprocess.PIPE, stdout=subprocess.PIPE)
            self._finalizer = weakref.finalize(self, _end, self._proc)  # also when the panel is just dropped
        return self._proc

    def run(self, job: str, arguments: Any, progress: Callable[[str], None]) -> Iterator[tuple]:
        """Run ``job`` in the child (on a worker thread: this blocks) and yield its parts.

        ``progress`` gets the child's progress lines; when it raises (the task was cancelled) the child
        is killed. Raises ``WorkFailed`` with the child's one line when the job failed."""
        with self._lock:
            proc = self._start()
            try:
                pickle.dump((job, arguments), proc.stdin, protocol=pickle.HIGHEST_PROTOCOL)
                proc.stdin.flush()
                yield from self._parts(proc.stdout, progress)
            except BaseException:
                self.kill()
                raise

    @staticmethod
    def _parts(stream: BinaryIO, progress: Callable[[str], None]) -> Iterator[tuple]:
        while True:
            kind, message = _reply(stream)
            if kind == "progress":
                progress(message[1])
            elif kind == "error":
                raise WorkFailed(message[1], _exit_code(message[2]))
            elif kind == "done":
                return
            else:
                yield message

    def kill(self) -> None:
        """Stop the child now (Cancel): a running job ends; the next one starts a new child."""
        proc, self._proc = self._proc, None
        if proc is not None and proc.poll() is None:
            proc.kill()
            proc.wait()

    def close(self) -> None:
        """End the child: its stdin closes and it exits (killed after 2 s if it is busy). Returns at once:
        a daemon thread waits for it (the GUI thread never does)."""
        proc, self._proc = self._proc, None
        if proc is not None:
            _end(proc)


def child_command() -> list[str]:
    """The child's command line: ``python -I`` (no ``PYTHON*`` variables, no user site, and not the
    current folder on ``sys.path``, where a ``pickle.py`` of the user's would be imported) with this
    process's absolute ``sys.path`` entries put first explicitly, so it finds ltl_stack and ROS as
    this process does. A relative entry (``''``: the current folder) is left out."""
    cwd = os.path.realpath(os.getcwd())
    paths = [p for p in sys.path if p and os.path.isabs(p) and os.path.realpath(p) != cwd]
    package_root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    if package_root not in paths:  # a fallback after the paths this process found ltl_stack through
        paths.append(package_root)
    boot = (f"import sys; sys.path[:0] = {paths!r}; sys.path[:] = [p for p in sys.path if p]; "
            "from ltl_stack.gui.worker_process import main; main()")
    return [sys.executable, "-I", "-c", boot]


#: what a reply may be: its kind and the types of what follows it (parts are checked by their reader)
_REPLY_SHAPES = {"progress": (str,), "error": (str, int), "done": ()}


def _reply(stream: BinaryIO) -> tuple[str, tuple]:
    """One reply of the child, checked: ``WorkFailed`` (one line) when the child ended or wrote
    something that is not a reply (garbage on its stdout: a module of ours printing there, or a
    broken child), instead of a raw exception reaching the panel."""
    try:
        message = pickle.load(stream)
    except EOFError:
        raise WorkFailed("the worker process ended unexpectedly", Exit.NEGATIVE) from None
    except Exception as err:  # noqa: BLE001 - any unreadable bytes: pickle raises many kinds
        raise WorkFailed(f"the worker process sent an unreadable reply ({type(err).__name__})", Exit.NEGATIVE) from None
    if not isinstance(message, tuple) or not message or not isinstance(message[0], str):
        raise WorkFailed(f"the worker process sent a malformed reply ({_shown(message)})", Exit.NEGATIVE)
    shape = _REPLY_SHAPES.get(message[0])
    if shape is not None and (len(message) != len(shape) + 1
                              or not all(isinstance(message[i + 1], kind) for i, kind in enumerate(shape))):
        raise WorkFailed(f"the worker process sent a malformed {message[0]!r} reply ({_shown(message)})",
                         Exit.NEGATIVE)
    return message[0], message


def _exit_code(code: int) -> Exit:
    try:
        return Exit(code)
    except ValueError:
        return Exit.NEGATIVE


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:56] + "…"


def analysis_view(worker: WorkerProcess | None, request: dict[str, Any],
                  progress: Callable[[str], None]) -> AnalysisView:
    """An analysis (``analyze_request``) in ``worker``'s process, or on this thread without one."""
    parts = (worker.run("analysis", request, progress) if worker is not None
             else analyze_request(request, progress).parts())
    view = AnalysisView.assemble(parts)
    view.snapshot = request.get("snapshot")
    return view


def controller_model(worker: WorkerProcess | None, spec: str, options: Any,
                     progress: Callable[[str], None]) -> ControllerModel:
    """``ControllerModel.synthesize`` with the synthesis in ``worker``'s process, or on this thread
    without one."""
    if worker is None:
        return ControllerModel.synthesize(spec, options, progress)
    return ControllerModel.assemble(spec, options, worker.run("automaton", {"spec": spec, "options": options},
                                                             progress))


def _end(proc: subprocess.Popen) -> None:
    if proc.poll() is not None:
        return
    try:
        proc.stdin.close()
    except OSError:
        pass

    def reap() -> None:
        try:
            proc.wait(timeout=2)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    threading.Thread(target=reap, name="ltl_stack_worker_reaper", daemon=True).start()


def _serve(requests: BinaryIO, replies: BinaryIO) -> None:
    def send(message: tuple) -> None:
        pickle.dump(message, replies, protocol=pickle.HIGHEST_PROTOCOL)
        replies.flush()

    while True:
        try:
            job, arguments = pickle.load(requests)
        except EOFError:
            return
        if job not in JOBS:
            send(("error", f"unknown job {job!r}", int(Exit.NEGATIVE)))
            continue
        gc.disable()  # neither job makes reference cycles; a full collection only costs time
        try:
            for part in JOBS[job](arguments, lambda text: send(("progress", text))):
                send(part)
            send(("done",))
        except (UserError, OSError, ValueError) as err:
            send(("error", str(err), int(err.code if isinstance(err, UserError) else Exit.BAD_INPUT)))
        except Exception as err:  # noqa: BLE001 - a bug: the traceback goes to stderr, the panel says so
            traceback.print_exc()
            send(("error", f"{type(err).__name__}: {err}", int(Exit.NEGATIVE)))
        finally:
            gc.enable()


def main() -> None:
    """The child: requests on stdin, replies on stdout; anything printed goes to stderr instead."""
    replies = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    _serve(sys.stdin.buffer, replies)


if __name__ == "__main__":
    main()

"""The analysis panel's analyses, in a process of their own. Qt-free.

A worker thread running the analysis' Python code stalled the panel's GUI thread: every event PyQt
hands to Python waits for the GIL, and on a loaded machine the worker is often descheduled while it
holds it (bench_gui --pictures: 61 ms with the GIL handed over every 0.2 ms, six busy processes beside
it). In a process of its own the analysis shares no GIL with the GUI. It sends its result in small
parts (``AnalysisResult.parts``) that the panel's worker thread reads one by one, each read short.
Cancel kills the process: the work really stops.

Protocol on the child's stdin/stdout, one pickle per message. Request: ``{"spec": ..., "mapping": ...,
"snapshot": Snapshot | None, "snapshot_path": ..., "robots": [...], "ignore_topics": [...]}``. Replies:
``("progress", text)``, then the parts and ``("done",)``, or ``("error", text, code, user_error)``.
The child ends when its stdin closes (the panel closed, or its process ended).
"""
from __future__ import annotations

import gc
import os
import pickle
import subprocess
import sys
import threading
import traceback
from collections.abc import Callable, Iterator
from typing import Any, BinaryIO

from ltl_stack.errors import Exit, UserError
from ltl_stack.gui.analysis_model import AnalysisResult, AnalysisView, run_analysis


def analyze_request(request: dict[str, Any], progress: Callable[[str], None]) -> AnalysisResult:
    """One request of the protocol, analysed in this process."""
    return run_analysis(request["spec"], request["mapping"], snapshot=request.get("snapshot"),
                        snapshot_path=request.get("snapshot_path"), robots=request.get("robots", ()),
                        ignore_topics=request.get("ignore_topics", ()), progress=progress)


class AnalysisFailed(UserError):
    """The analysis in the child process failed; the message is what the panel shows."""


class AnalysisProcess:
    """One child process that analyses, reused from one analysis to the next (it starts once)."""

    def __init__(self) -> None:
        self._proc: subprocess.Popen | None = None
        self._lock = threading.Lock()

    def _start(self) -> subprocess.Popen:
        if self._proc is None or self._proc.poll() is not None:
            env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))  # as this process finds ltl_stack
            self._proc = subprocess.Popen([sys.executable, "-m", "ltl_stack.gui.analysis_process"],
                                          stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
        return self._proc

    def analyze(self, request: dict[str, Any], progress: Callable[[str], None]) -> AnalysisView:
        """Run one analysis in the child (on a worker thread: this blocks until it is done).

        ``progress`` gets the child's progress lines; when it raises (the task was cancelled) the child
        is killed. Raises ``AnalysisFailed`` with the child's one line on a failed analysis."""
        with self._lock:
            proc = self._start()
            try:
                pickle.dump(request, proc.stdin, protocol=pickle.HIGHEST_PROTOCOL)
                proc.stdin.flush()
                view = AnalysisView.assemble(self._parts(proc.stdout, progress))
            except BaseException:
                self.kill()
                raise
            view.snapshot = request.get("snapshot")
            return view

    @staticmethod
    def _parts(stream: BinaryIO, progress: Callable[[str], None]) -> Iterator[tuple]:
        while True:
            try:
                message = pickle.load(stream)
            except EOFError:
                raise AnalysisFailed("the analysis process ended unexpectedly", Exit.NEGATIVE) from None
            kind = message[0]
            if kind == "progress":
                progress(message[1])
            elif kind == "error":
                _kind, text, code, _user = message
                raise AnalysisFailed(text, Exit(code))
            elif kind == "done":
                return
            else:
                yield message

    def kill(self) -> None:
        """Stop the child now (Cancel): a running analysis ends; the next one starts a new child."""
        proc, self._proc = self._proc, None
        if proc is not None and proc.poll() is None:
            proc.kill()
            proc.wait()

    def close(self) -> None:
        """End the child (its stdin closes and it exits; killed if it is busy)."""
        proc, self._proc = self._proc, None
        if proc is None:
            return
        if proc.poll() is None:
            try:
                proc.stdin.close()
                proc.wait(timeout=2)
            except (OSError, subprocess.TimeoutExpired):
                proc.kill()
                proc.wait()


def _serve(requests: BinaryIO, replies: BinaryIO) -> None:
    def send(message: tuple) -> None:
        pickle.dump(message, replies, protocol=pickle.HIGHEST_PROTOCOL)
        replies.flush()

    while True:
        try:
            request = pickle.load(requests)
        except EOFError:
            return
        gc.disable()  # the analysis makes no reference cycles; a full collection only costs time
        try:
            result = analyze_request(request, lambda text: send(("progress", text)))
            for part in result.parts():
                send(part)
            send(("done",))
        except (UserError, OSError, ValueError) as err:
            code = err.code if isinstance(err, UserError) else Exit.BAD_INPUT
            send(("error", str(err), int(code), True))
        except Exception as err:  # noqa: BLE001 - a bug: the traceback goes to stderr, the panel says so
            traceback.print_exc()
            send(("error", f"{type(err).__name__}: {err}", int(Exit.NEGATIVE), False))
        finally:
            result = None
            gc.enable()


def main() -> None:
    """The child: requests on stdin, replies on stdout; anything printed goes to stderr instead."""
    replies = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    _serve(sys.stdin.buffer, replies)


if __name__ == "__main__":
    main()

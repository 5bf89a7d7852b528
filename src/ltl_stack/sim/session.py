"""Run ROS processes against a private rosmaster: what the demo and scenario runners need.

A ``RosSession`` starts ``rosmaster`` on a free loopback port (never the default 11311, which a
user may be using), gives every child process an environment pointing at it and stops them all,
master last, on exit — also on Ctrl-C or an exception.
"""
from __future__ import annotations

import os
import signal
import socket
import subprocess
import tempfile
import threading
import time
import xmlrpc.client
from collections.abc import Sequence
from pathlib import Path


def free_port() -> int:
    """A loopback TCP port nothing listens on now, other than 11311."""
    while True:
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if port != 11311:
            return port


def master_env(port: int, workdir: Path) -> dict[str, str]:
    """This process's environment pointed at a master on ``port``, with logs kept under ``workdir``."""
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}/", ROS_IP="127.0.0.1", PYTHONUNBUFFERED="1",
               ROS_LOG_DIR=str(workdir / "log"), ROS_HOME=str(workdir / "ros_home"))
    env.pop("ROS_HOSTNAME", None)
    return env


def master_command(port: int) -> list[str]:
    """The command line of a bare rosmaster on ``port``."""
    return ["rosmaster", "--core", "-p", str(port), "-w", "4"]


def await_master(uri: str, master: subprocess.Popen, log_path: Path, run_id: str, timeout: float = 20.0) -> None:
    """Wait until the master at ``uri`` answers, then set ``/run_id`` as roscore does (roslaunch expects
    it when it joins an existing master). RuntimeError, with the master's log, when it exits or stays silent."""
    deadline = time.monotonic() + timeout
    proxy = xmlrpc.client.ServerProxy(uri)
    while True:
        if master.poll() is not None:
            raise RuntimeError(f"rosmaster exited:\n{log_path.read_text(errors='replace')[-4000:]}")
        try:
            proxy.getSystemState("/ltl_stack")
            break
        except OSError:
            if time.monotonic() > deadline:
                raise RuntimeError(f"rosmaster did not answer on {uri} within {timeout:.0f} s") from None
            time.sleep(0.05)
    proxy.setParam("/ltl_stack", "/run_id", run_id)


class RosSession:
    """A private master and the processes started against it (use as a context manager)."""

    def __init__(self, workdir: Path | None = None, port: int | None = None, master_uri: str | None = None):
        """``master_uri``: use that running master instead of starting a private one (the nodes then
        keep the caller's ROS_IP/ROS_HOSTNAME: the master may be on another host)."""
        self._tmp = None if workdir else tempfile.TemporaryDirectory(prefix="ltl_stack-")
        self.workdir = Path(workdir or self._tmp.name)
        self.port = port or free_port()
        self.env = master_env(self.port, self.workdir)
        if master_uri:
            self.env["ROS_MASTER_URI"] = master_uri
            # A master on another host reaches our nodes at the caller's address, not at 127.0.0.1.
            for key in ("ROS_IP", "ROS_HOSTNAME"):
                if key in os.environ:
                    self.env[key] = os.environ[key]
                else:
                    self.env.pop(key, None)
        self.own_master = not master_uri
        self.uri = self.env["ROS_MASTER_URI"]
        self.processes: list[subprocess.Popen] = []
        self._sigterm: object = None

    def __enter__(self) -> RosSession:
        # Started as a background job of a non-interactive shell, this process ignores SIGINT and its
        # children would inherit that: rosmaster and nodes without rospy's handler would then outlast
        # the SIGINT that stops them (stop_process) by its whole grace period. A handled signal is reset
        # to the default in a child, so handle it here as Python does by default.
        main = threading.current_thread() is threading.main_thread()
        if main and signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
            signal.signal(signal.SIGINT, signal.default_int_handler)
        # The children run in sessions of their own, so a SIGTERM (kill, a supervisor, a test's
        # terminate()) that ended this process at once left them running: end through __exit__ instead.
        self._sigterm = signal.getsignal(signal.SIGTERM) if main else None
        if self._sigterm is signal.SIG_DFL:
            signal.signal(signal.SIGTERM, _exit_on_sigterm)
        if not self.own_master:
            return self
        log_path = self.workdir / "rosmaster.log"
        master = self.start(master_command(self.port), stdout=open(log_path, "wb"))  # noqa: SIM115
        await_master(self.uri, master, log_path, f"ltl_stack-{self.port}")
        return self

    def start(self, args: Sequence[str], stdout=None) -> subprocess.Popen:
        """Start a child process against this session's master."""
        proc = subprocess.Popen(list(args), env=self.env, stdout=stdout if stdout is not None else subprocess.PIPE,
                                stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, start_new_session=True)
        self.processes.append(proc)
        return proc

    def __exit__(self, *exc) -> None:
        for proc in reversed(self.processes):
            stop_process(proc)
        if self._tmp is not None:
            self._tmp.cleanup()
        if self._sigterm is signal.SIG_DFL:
            signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _exit_on_sigterm(signum: int, _frame: object) -> None:
    """SIGTERM ends a session's program as Ctrl-C does: its processes are stopped on the way out."""
    raise SystemExit(128 + signum)


def stop_process(proc: subprocess.Popen, timeout: float = 5.0) -> None:
    """SIGINT the process group (as Ctrl-C would), escalating to SIGKILL; then stop whatever it left
    behind (``stop_leftovers``: roslaunch starts every node in a session of its own)."""
    if proc.poll() is not None:
        return  # its children, if any, are no longer below it: nothing to find
    tree = descendants(proc.pid)
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
        if proc.poll() is not None:
            break
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(timeout)
            break
        except subprocess.TimeoutExpired:
            continue
    stop_leftovers(tree, timeout)


def _stat(pid: int) -> list[str] | None:
    """The fields of /proc/PID/stat after the command name (state, ppid, …), or None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text[text.rindex(")") + 2:].split()


def descendants(pid: int) -> list[tuple[int, str]]:
    """Every process below ``pid`` as (pid, start time) pairs, read from /proc (empty elsewhere).

    Signalling a process group does not reach them all: roslaunch puts each node in a session of
    its own, and a roslaunch killed before it has stopped its nodes leaves them running."""
    children: dict[int, list[int]] = {}
    started: dict[int, str] = {}
    try:
        entries = [int(e.name) for e in os.scandir("/proc") if e.name.isdigit()]
    except OSError:
        return []
    for child in entries:
        fields = _stat(child)
        if fields and len(fields) > 19:
            children.setdefault(int(fields[1]), []).append(child)
            started[child] = fields[19]
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append((child, started[child]))
            todo.append(child)
    return found


def stop_leftovers(tree: Sequence[tuple[int, str]], timeout: float = 5.0) -> None:
    """SIGINT, then SIGKILL, the processes of ``tree`` that still run (the same process: same start time)."""
    for sig in (signal.SIGINT, signal.SIGKILL):
        alive = _running(tree)
        for pid in alive:
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + timeout
        while alive and time.monotonic() < deadline:
            alive = _running(tree)
            time.sleep(0.05)


def _running(tree: Sequence[tuple[int, str]]) -> list[int]:
    return [pid for pid, start in tree if (fields := _stat(pid)) and fields[19] == start and fields[0] != "Z"]

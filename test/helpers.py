"""Helpers for tests that run real ROS processes: free ports, waiting, starting nodes, shared data."""
from __future__ import annotations

import http.client
import importlib.util
import json
import os
import random
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import pytest

from ltl_stack.sim.session import (  # noqa: F401 - free_port for tests
    descendants,
    free_port,
    master_command,
    master_env,
    stop_leftovers,
    stop_process,
)

_HELD: list[socket.socket] = []


def closed_port() -> int:
    """A loopback port that refuses connections for the whole test session: bound here, never listened
    on, so no other process (a node's XML-RPC server, another worker's master) can take it meanwhile.
    ``free_port`` only says a port is free *now*."""
    held = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    held.bind(("127.0.0.1", 0))
    _HELD.append(held)
    return held.getsockname()[1]

REPO_ROOT = Path(__file__).resolve().parent.parent

#: whether Debian's ROS Python modules can be imported here (not under the Python matrix's 3.12/3.13)
ROS_PYTHON = importlib.util.find_spec("rosgraph") is not None and importlib.util.find_spec("rospy") is not None
#: the scripts that run without Debian's ROS Python modules; every other one imports rospy, rosgraph or genpy
ROS_FREE_SCRIPTS = frozenset({"synthesize", "generate_launch", "mine_channels"})


def _bdd_backend() -> str:
    from ltl_stack.synthesis.game import BACKEND

    return BACKEND


#: the BDD package synthesis runs on here: "cudd", or "autoref" (dd's pure-Python BDDs: Python 3.8,
#: whose dd has no CUDD wheel; docs/python_versions.md)
BDD_BACKEND = _bdd_backend()

#: a test of what only CUDD does (the memory cap of --max-memory, dynamic reordering and its counts, the
#: manager's statistics); Python 3.8's dd has no CUDD (docs/python_versions.md), and there synthesis
#: runs on dd.autoref, which the rest of the suite tests
needs_cudd = pytest.mark.skipif(BDD_BACKEND != "cudd",
                                reason="needs dd.cudd (CUDD), which this Python's dd wheel lacks")

#: a test that solves large games (or many): on dd.autoref each takes minutes of a busy machine's CPU,
#: more than the whole rest of the 3.8 unit leg; test/conftest.py skips it there, saying why, as it does
#: the tests listed in PURE_PYTHON_DD_HEAVY (the same code runs on CUDD in every other leg, and
#: dd.autoref's answers are compared with CUDD's by test_pure_python_dd.py)
heavy_game = pytest.mark.heavy_game
HEAVY_GAME_REASON = ("solves games that take over 5 s of CPU on pure-Python dd (dd.autoref; this Python's dd has "
                     "no CUDD), beyond the 3.8 leg's budget; the runs with CUDD (Python 3.9-3.13) check it")
#: the measured list of such tests that carry no marker (test ids, one a line, after their CPU seconds)
PURE_PYTHON_DD_HEAVY = Path(__file__).resolve().parent / "pure_python_dd_heavy.txt"


def pure_python_dd_heavy() -> set[str]:
    """The test ids of ``PURE_PYTHON_DD_HEAVY`` (a function's id without ``[...]`` stands for all its cases)."""
    lines = PURE_PYTHON_DD_HEAVY.read_text().splitlines()
    return {line.split()[-1] for line in lines if line.strip() and not line.startswith("#")}


def script_marks(tool: str) -> list[pytest.MarkDecorator]:
    """``ros_python`` for a case that runs a script needing Debian's ROS Python modules."""
    return [] if tool in ROS_FREE_SCRIPTS else [pytest.mark.ros_python]


def bootstrap_paths() -> dict[str, Path]:
    """Where tools/bootstrap.sh keeps what it builds for this clone (tools/paths.sh): home, venv, ws."""
    out = subprocess.run(["bash", "-c", 'source tools/paths.sh && echo "$LTL_STACK_HOME" && '
                          'echo "$LTL_STACK_VENV" && echo "$LTL_STACK_WS"'], cwd=REPO_ROOT, capture_output=True,
                         text=True, check=True, timeout=300).stdout.split("\n")
    return {"home": Path(out[0]), "venv": Path(out[1]), "ws": Path(out[2])}


def shared_dir() -> Path | None:
    """The project's ``../shared`` folder (specs, robots, thesis), or None when it is absent."""
    candidate = REPO_ROOT.parent / "shared"
    return candidate if candidate.is_dir() else None


def require_shared(*parts: str) -> Path:
    """Path inside ``../shared``; skips the calling test, saying why, when it is not there."""
    base = shared_dir()
    if base is None:
        pytest.skip(f"../shared is absent (looked for {REPO_ROOT.parent / 'shared'})")
    path = base.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"shared file {path} is absent")
    return path


#: The start of a test's node script that prints from rospy callbacks: ``say`` prints one whole line
#: (rospy calls back from a thread per connection, and ``print`` writes a line in pieces that another
#: thread's can split).
SAY = '''
import sys
import threading

_lock = threading.Lock()


def say(*parts):
    with _lock:
        sys.stdout.write(" ".join(str(p) for p in parts) + "\\n")
        sys.stdout.flush()
'''

# How long a test waits for something that must happen. Generous: on a busy 2-core machine a node
# can take many seconds to start. A test never asserts how fast something happens (benchmarks do).
WAIT = 60.0
#: Every ``wait_for`` waits this many times the timeout it is given: the timeouts written in the tests
#: were measured on this machine kind under load, and a CI machine can stall longer (a connection that
#: rospy retries after 1, 2, 4 ... 32 s). A condition met returns at once, so a passing test pays nothing.
PATIENCE = float(os.environ.get("LTL_STACK_TEST_PATIENCE", "2"))


def wait_for(predicate: Callable[[], object], timeout: float = WAIT, what: str = "a condition",
             interval: float = 0.02) -> object:
    """Poll ``predicate`` until it returns something truthy; fail the test after ``timeout`` s times
    ``PATIENCE``."""
    timeout *= PATIENCE
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout:.1f} s waiting for {what}")
        time.sleep(interval)


def demo_states(stdout: str) -> list[dict]:
    """The states a ``demo --json`` run gave the robot, from its output. A state the controller
    settled through at once (its outputs never published; e.g. the initial one, whose outputs the
    spec may leave free) is told with ``"settling": true`` and the stamp of the state reached after
    it; whether the trace saw it depends on when it connected, so it is checked and left out."""
    states = [e for e in (json.loads(line) for line in stdout.splitlines() if line.startswith("{"))
              if e["event"] == "state"]
    for s in states:
        if s.get("settling"):
            assert any(o["time"] == s["time"] and not o.get("settling") for o in states), states
    return [s for s in states if not s.get("settling")]


def work(fn: Callable[[], object], weigh: Callable[[object], int] | None = None) -> int:
    """The work ``fn`` does, counted rather than timed (the machine is shared): every Python and C
    function call made while it runs, plus ``weigh(frame)`` for each Python call (e.g. the operands an
    n-ary node copies). Linearity is checked by comparing the work of a small and a large input."""
    count = 0

    def profile(frame, event, arg) -> None:
        nonlocal count
        if event == "call":
            count += 1 + (weigh(frame) if weigh else 0)
        elif event == "c_call":
            count += 1

    old = sys.getprofile()
    sys.setprofile(profile)
    try:
        fn()
    finally:
        sys.setprofile(old)
    return count


class RosProcess:
    """A child process (a node, roslaunch, rosrun) whose output goes to a log file."""

    def __init__(self, args: Sequence[str], env: Mapping[str, str], log_path: Path,
                 cwd: Path | None = None):
        self.args = list(args)
        self.log_path = log_path
        self._log = open(log_path, "wb")  # noqa: SIM115 - closed in stop()
        self.popen = subprocess.Popen(self.args, env=dict(env), stdout=self._log, stderr=subprocess.STDOUT,
                                      stdin=subprocess.DEVNULL, cwd=cwd, start_new_session=True)

    def output(self) -> str:
        """Everything the process printed so far."""
        return self.log_path.read_text(errors="replace")

    def wait_output(self, text: str, timeout: float = WAIT) -> str:
        """Wait until ``text`` appears in the output; fails with the output shown."""
        try:
            wait_for(lambda: text in self.output(), timeout, f"{text!r} in the output of {self.args}")
        except AssertionError as err:
            raise AssertionError(f"{err}\n--- output ---\n{self.output()[-4000:]}") from None
        return self.output()

    def running(self) -> bool:
        return self.popen.poll() is None

    def stop(self, timeout: float = 5.0) -> int | None:
        """SIGINT the process group (as Ctrl-C would), then SIGTERM, then SIGKILL if it lingers."""
        stop_process(self.popen, timeout)
        self._log.close()
        return self.popen.returncode


#: test masters' ports start above ROS' default master port 11311, which the suite never uses
FIRST_TEST_PORT = 11400


def _port_range() -> range:
    """Ports for test masters: below the kernel's ephemeral range, where every node binds its own
    servers (port 0), so no node can take a master's port; one slice per pytest-xdist worker."""
    try:
        low = int(Path("/proc/sys/net/ipv4/ip_local_port_range").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        low = 32768
    low = max(low, 12000)
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0")[2:]
    slices = 8
    index = int(worker) % slices if worker.isdigit() else 0
    width = (low - FIRST_TEST_PORT) // slices
    start = FIRST_TEST_PORT + index * width
    return range(start, start + width)


def _port_is_free(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
    return port != 11311


def direct_script(args: Sequence[str], env: Mapping[str, str]) -> list[str]:
    """``rosrun ltl_stack SCRIPT ARGS`` as ``PREFIX/lib/ltl_stack/SCRIPT ARGS``: the same catkin-generated
    script that rosrun would find, without rosrun's package search (~0.5 s per process on a busy
    machine, and the suite starts hundreds). rosrun itself is tested by test_scripts and the
    install-space test; other commands are returned as they are."""
    if len(args) > 2 and args[0] == "rosrun" and args[1] == "ltl_stack":
        for prefix in env.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
            script = Path(prefix) / "lib" / "ltl_stack" / args[2]
            if prefix and script.is_file() and os.access(script, os.X_OK):
                return [str(script), *args[3:]]
    return list(args)


def run_script(args: Sequence[str], **kwargs) -> subprocess.CompletedProcess:
    """``subprocess.run`` of ``rosrun ltl_stack SCRIPT ARGS`` through ``direct_script`` (with the
    ``env`` given, else this process's)."""
    return subprocess.run(direct_script(args, kwargs.get("env") or os.environ), **kwargs)


def folder_files(folder: Path) -> dict[str, bytes | str]:
    """Every entry of ``folder`` and its bytes, to check that a refused call changed nothing."""
    return {p.name: p.read_bytes() if p.is_file() else "not a regular file" for p in sorted(folder.iterdir())}


def run_case(master: RosMaster, folder: Path, command: list[str], files: Mapping[str, bytes | None],
             env: Mapping[str, str] | None = None) -> tuple[subprocess.CompletedProcess, dict]:
    """One row of a bad-input table: write ``files`` into ``folder`` (``None``: a FIFO, never read),
    run ``rosrun ltl_stack COMMAND`` there (``{d}`` in an argument is the folder) against ``master``;
    (the finished process, the folder's files before it ran)."""
    for name, data in files.items():
        if data is None:
            os.mkfifo(folder / name)
        else:
            (folder / name).write_bytes(data)
    before = folder_files(folder)
    args = [a.replace("{d}", str(folder)) for a in command]
    env = dict(master.env, **(env or {}))
    done = subprocess.run(direct_script(["rosrun", "ltl_stack", *args], env), env=env, capture_output=True,
                          text=True, errors="surrogateescape", timeout=300, cwd=folder)
    return done, before


def assert_one_error_line(done: subprocess.CompletedProcess, tool: str, code: int, message: str) -> None:
    """A tool refused its input: exit ``code``, exactly one ``<tool>: error:`` line holding ``message``
    (the tool's name not repeated), every stderr line the tool's own, no traceback."""
    assert done.returncode == code, (done.returncode, done.stdout[-1000:], done.stderr[-2000:])
    errors = [line for line in (done.stdout + done.stderr).splitlines() if "error:" in line.lower()]
    assert len(errors) == 1, done.stderr[-2000:]
    # no continuation line: every line is the tool's own (progress, or the one error)
    assert all(line.startswith(f"{tool}: ") for line in done.stderr.splitlines()), done.stderr[-2000:]
    assert errors[0].startswith(f"{tool}: error: ") and errors[0].count("error:") == 1, errors
    assert not errors[0].startswith(f"{tool}: error: {tool}: "), errors
    assert message in errors[0], errors
    assert "Traceback" not in done.stderr + done.stdout, done.stderr[-3000:]


def assert_one_fatal_line(done: subprocess.CompletedProcess, message: str) -> None:
    """A node refused its parameters or files: exit 2, exactly one ``[FATAL]`` line holding
    ``message``, no traceback."""
    assert done.returncode == 2, (done.returncode, done.stdout[-1000:], done.stderr[-2000:])
    out = done.stdout + done.stderr
    fatal = [line for line in out.splitlines() if "[FATAL]" in line]
    assert len(fatal) == 1 and message in fatal[0], out[-2000:]
    assert "Traceback" not in out, out[-3000:]


class RosMaster:
    """A real rosmaster on a free loopback port, and the processes started against it.

    Several suites and pytest-xdist workers start masters at once: a port is taken from this worker's
    slice, and the master counts as up only when the process that answers on it is ours (``getPid``);
    otherwise (another master or node won the port) it is stopped and another port is tried.
    """

    def __init__(self, workdir: Path, attempts: int = 20, timeout: float = 60.0):
        self.workdir = workdir
        self.processes: list[RosProcess] = []
        ports = _port_range()
        for attempt in range(attempts):
            port = random.choice(ports)
            if not _port_is_free(port):
                continue
            env = master_env(port, workdir)
            master = RosProcess(master_command(port), env, workdir / f"rosmaster-{attempt}.log")
            if self._answers(master, env["ROS_MASTER_URI"], timeout):
                break
            master.stop()
        else:
            raise RuntimeError(f"no rosmaster came up in {attempts} attempts; logs in {workdir}")
        self.port, self.env, self.uri, self._master = port, env, env["ROS_MASTER_URI"], master
        self.proxy().setParam("/pytest", "/run_id", f"pytest-{port}")  # roslaunch expects it, as from roscore

    @staticmethod
    def _answers(master: RosProcess, uri: str, timeout: float) -> bool:
        """True once the master at ``uri`` answers and is ``master``; False if that cannot happen."""
        proxy = xmlrpc.client.ServerProxy(uri)
        deadline = time.monotonic() + timeout
        while master.running() and time.monotonic() < deadline:
            try:
                code, _, pid = proxy.getPid("/pytest")
                return code == 1 and pid == master.popen.pid
            except (OSError, http.client.HTTPException, xmlrpc.client.Error):
                time.sleep(0.05)
        return False

    def proxy(self):
        import xmlrpc.client

        return xmlrpc.client.ServerProxy(self.uri)

    def system_state(self) -> tuple[list, list, list]:
        """(publishers, subscribers, services) as the master reports them."""
        code, msg, state = self.proxy().getSystemState("/pytest")
        assert code == 1, msg
        return state

    def publishers(self, topic: str) -> list[str]:
        return next((nodes for name, nodes in self.system_state()[0] if name == topic), [])

    def subscribers(self, topic: str) -> list[str]:
        return next((nodes for name, nodes in self.system_state()[1] if name == topic), [])

    def wait_for_publisher(self, topic: str, timeout: float = WAIT) -> list[str]:
        return wait_for(lambda: self.publishers(topic), timeout, f"a publisher on {topic}")

    def wait_for_subscriber(self, topic: str, timeout: float = WAIT) -> list[str]:
        return wait_for(lambda: self.subscribers(topic), timeout, f"a subscriber on {topic}")

    def restart_master(self, run_id: bool = True) -> None:
        """Stop the master and start a new, empty one on the same port; the nodes keep running.
        ``run_id``: set ``/run_id`` as roscore does (False: a bare rosmaster, without it)."""
        self._master.stop()
        restarts = len(list(self.workdir.glob("rosmaster*.log")))
        self._master = RosProcess(master_command(self.port), self.env, self.workdir / f"rosmaster-{restarts}.log")
        if not self._answers(self._master, self.uri, 60.0):
            raise RuntimeError(f"no new rosmaster on port {self.port}; logs in {self.workdir}")
        if run_id:
            self.proxy().setParam("/pytest", "/run_id", f"pytest-{self.port}-{restarts}")

    def run(self, args: Sequence[str], name: str | None = None, cwd: Path | None = None) -> RosProcess:
        """Start a process (e.g. ``['rosrun', 'ltl_stack', 'proposition_monitor', ...]``) on this master."""
        label = name or Path(args[2] if args[0] in ("rosrun", "roslaunch") and len(args) > 2 else args[0]).name
        args = direct_script(args, self.env)
        log = self.workdir / f"{len(self.processes):02d}-{label}.log"
        proc = RosProcess(args, self.env, log, cwd=cwd)
        self.processes.append(proc)
        return proc

    def shutdown(self) -> None:
        stop_all(self.processes)
        self._master.stop()


def stop_all(processes: Sequence[RosProcess], timeout: float = 5.0) -> None:
    """Stop every process as ``RosProcess.stop`` does, all at once (a scenario has dozens of nodes),
    and what they leave behind (the nodes of a roslaunch that had to be killed)."""
    trees = [node for p in processes if p.running() for node in descendants(p.popen.pid)]
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
        alive = [p for p in processes if p.running()]
        for proc in alive:
            try:
                os.killpg(proc.popen.pid, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + timeout
        for proc in alive:
            try:
                proc.popen.wait(max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                pass
    stop_leftovers(trees, timeout)
    for proc in processes:
        proc.stop()  # closes the log; the process is gone already


def start_node(master: RosMaster, args: Sequence[str], name: str | None = None) -> RosProcess:
    """Start a node against ``master``; it is stopped when the master fixture ends."""
    return master.run(args, name=name)

"""Helpers for tests that run real ROS processes: free ports, waiting, starting nodes, shared data."""
from __future__ import annotations

import subprocess
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import pytest

from ltl_stack.sim.session import await_master, free_port, master_command, master_env, stop_process

REPO_ROOT = Path(__file__).resolve().parent.parent


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


def wait_for(predicate: Callable[[], object], timeout: float = 10.0, what: str = "a condition",
             interval: float = 0.02) -> object:
    """Poll ``predicate`` until it returns something truthy; fail the test after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout:.1f} s waiting for {what}")
        time.sleep(interval)


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

    def wait_output(self, text: str, timeout: float = 10.0) -> str:
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


class RosMaster:
    """A real rosmaster on a free loopback port, and the processes started against it."""

    def __init__(self, workdir: Path):
        self.port = free_port()
        self.workdir = workdir
        self.env = master_env(self.port, workdir)
        self.uri = self.env["ROS_MASTER_URI"]
        self.processes: list[RosProcess] = []
        self._master = RosProcess(master_command(self.port), self.env, workdir / "rosmaster.log")
        await_master(self.uri, self._master.popen, self._master.log_path, f"pytest-{self.port}")

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

    def wait_for_publisher(self, topic: str, timeout: float = 15.0) -> list[str]:
        return wait_for(lambda: self.publishers(topic), timeout, f"a publisher on {topic}")

    def wait_for_subscriber(self, topic: str, timeout: float = 15.0) -> list[str]:
        return wait_for(lambda: self.subscribers(topic), timeout, f"a subscriber on {topic}")

    def run(self, args: Sequence[str], name: str | None = None, cwd: Path | None = None) -> RosProcess:
        """Start a process (e.g. ``['rosrun', 'ltl_stack', 'proposition_monitor', ...]``) on this master."""
        label = name or Path(args[2] if args[0] in ("rosrun", "roslaunch") and len(args) > 2 else args[0]).name
        log = self.workdir / f"{len(self.processes):02d}-{label}.log"
        proc = RosProcess(args, self.env, log, cwd=cwd)
        self.processes.append(proc)
        return proc

    def shutdown(self) -> None:
        for proc in reversed(self.processes):
            proc.stop()
        self._master.stop()


def start_node(master: RosMaster, args: Sequence[str], name: str | None = None) -> RosProcess:
    """Start a node against ``master``; it is stopped when the master fixture ends."""
    return master.run(args, name=name)

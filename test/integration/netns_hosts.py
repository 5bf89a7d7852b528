"""Emulated hosts for integration tests: network namespaces joined by veth pairs to one bridge.

Each "host" is a namespace with one interface (``eth0``, 10.232.0.K/24) whose peer is a port of a
bridge in a "switch" namespace; nothing is created in this process's own namespace. Neighbour
entries are permanent, so a partition is silent as on a real network (no ARP failure tells the
sender at once). ``cut(host)`` takes the host's port off the bridge (its processes keep running,
their packets go nowhere, connects hang until their timeout); ``heal(host)`` puts it back. Processes run in a host with ``ip netns exec``, their
ROS_IP set to the host's address. Names contain ``$LTL_STACK_NETNS_TAG`` (default ``i32``), the xdist worker and this process id, so
concurrent workers never share one; ``close`` removes every namespace (and with it every link).
"""
from __future__ import annotations

import os
import subprocess
from collections.abc import Mapping, Sequence
from pathlib import Path

from helpers import RosProcess, stop_all, wait_for

SUBNET = "10.232.0"


def _ip(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run(["ip", *args], capture_output=True, text=True, check=check, timeout=30)


def netns_refusal() -> str | None:
    """Why emulated hosts cannot be made here (None: they can)."""
    if os.geteuid() != 0:
        return "network namespaces need root"
    probe = f"i32probe{os.getpid()}"
    try:
        made = _ip("netns", "add", probe, check=False)
    except (OSError, subprocess.TimeoutExpired) as err:
        return f"ip netns is not available: {err}"
    if made.returncode != 0:
        return f"ip netns add is not permitted: {made.stderr.strip()}"
    _ip("netns", "del", probe, check=False)
    return None


class Hosts:
    """``count`` emulated hosts on one switch; host K has address ``address(K)``."""

    def __init__(self, workdir: Path, count: int) -> None:
        worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0")
        self.prefix = f"{os.environ.get('LTL_STACK_NETNS_TAG', 'i32')}{worker}p{os.getpid()}"
        self.workdir = workdir
        self.count = count
        self.processes: list[RosProcess] = []
        self.namespaces: list[str] = []
        try:
            self._build()
        except BaseException:
            self.close()
            raise

    def ns(self, host: int) -> str:
        return f"{self.prefix}h{host}"

    @property
    def switch(self) -> str:
        return f"{self.prefix}sw"

    def address(self, host: int) -> str:
        return f"{SUBNET}.{host + 1}"

    def _add(self, name: str) -> None:
        _ip("netns", "add", name)
        self.namespaces.append(name)
        _ip("-n", name, "link", "set", "lo", "up")

    def _build(self) -> None:
        self._add(self.switch)
        _ip("-n", self.switch, "link", "add", "br0", "type", "bridge")
        _ip("-n", self.switch, "link", "set", "br0", "up")
        for host in range(self.count):
            self._add(self.ns(host))
            _ip("link", "add", "eth0", "netns", self.ns(host), "type", "veth", "peer", "name", f"p{host}",
                "netns", self.switch)
            _ip("-n", self.switch, "link", "set", f"p{host}", "master", "br0")
            _ip("-n", self.switch, "link", "set", f"p{host}", "up")
            _ip("-n", self.ns(host), "addr", "add", f"{self.address(host)}/24", "dev", "eth0")
            _ip("-n", self.ns(host), "link", "set", "eth0", "up")
        macs = {host: self._mac(host) for host in range(self.count)}
        for host in range(self.count):
            for other in range(self.count):
                if other != host:
                    _ip("-n", self.ns(host), "neigh", "replace", self.address(other), "lladdr", macs[other],
                        "dev", "eth0", "nud", "permanent")

    def _mac(self, host: int) -> str:
        out = _ip("-n", self.ns(host), "-o", "link", "show", "eth0").stdout
        return out.split("link/ether")[1].split()[0]

    def make_lossy(self, host: int, delay: float, jitter: float, loss: float) -> RosProcess:
        """Put a user-space delay/loss forwarder (``lossy_forwarder.py``) between ``host`` and the
        bridge: its port leaves the bridge, a new veth pair joins it, the forwarder copies frames
        between the two with ``delay`` ± ``jitter`` s and probability ``loss`` of a drop."""
        _ip("-n", self.switch, "link", "add", f"q{host}", "type", "veth", "peer", "name", f"r{host}")
        _ip("-n", self.switch, "link", "set", f"r{host}", "master", "br0")
        for name in (f"q{host}", f"r{host}"):
            _ip("-n", self.switch, "link", "set", name, "up")
        _ip("-n", self.switch, "link", "set", f"p{host}", "nomaster")
        # frames copied in user space must be whole: checksums computed, no 64 KiB offload segments
        ends = [(self.ns(h), "eth0") for h in range(self.count)] + [(self.switch, d) for d in ("br0", f"p{host}",
                                                                                               f"q{host}", f"r{host}")]
        for ns, dev in ends:
            subprocess.run(["ip", "netns", "exec", ns, "ethtool", "-K", dev, "tx", "off", "tso", "off", "gso", "off",
                            "gro", "off"], capture_output=True, check=True, timeout=30)
        script = Path(__file__).with_name("lossy_forwarder.py")
        log = self.workdir / f"forwarder-h{host}.log"
        proc = RosProcess(["ip", "netns", "exec", self.switch, sys_python(), str(script), f"p{host}", f"q{host}",
                           str(delay), str(jitter), str(loss)], dict(os.environ), log)
        self.processes.append(proc)
        proc.wait_output("up", timeout=60)
        return proc

    def cut(self, host: int) -> None:
        """Partition ``host`` from every other one."""
        _ip("-n", self.switch, "link", "set", f"p{host}", "nomaster")

    def heal(self, host: int) -> None:
        _ip("-n", self.switch, "link", "set", f"p{host}", "master", "br0")

    def env(self, host: int, master_host: int, port: int) -> dict[str, str]:
        """The environment of a ROS process on ``host`` with the master on ``master_host``."""
        env = dict(os.environ, ROS_MASTER_URI=f"http://{self.address(master_host)}:{port}/",
                   ROS_IP=self.address(host), PYTHONUNBUFFERED="1", ROS_LOG_DIR=str(self.workdir / "log"),
                   ROS_HOME=str(self.workdir / "ros_home"))
        env.pop("ROS_HOSTNAME", None)
        return env

    def run(self, host: int, args: Sequence[str], env: Mapping[str, str], name: str) -> RosProcess:
        """Start ``args`` on ``host`` (stopped by ``close``)."""
        from helpers import direct_script

        log = self.workdir / f"{len(self.processes):02d}-h{host}-{name}.log"
        proc = RosProcess(["ip", "netns", "exec", self.ns(host), *direct_script(args, env)], env, log)
        self.processes.append(proc)
        return proc

    def close(self) -> None:
        stop_all(self.processes)
        for name in reversed(self.namespaces):
            _ip("netns", "del", name, check=False)
        self.namespaces = []


def reachable(hosts: Hosts, host: int, address: str, port: int) -> bool:
    """A TCP connection from ``host`` to ``address:port`` succeeds within 2 s."""
    code = f"import socket; socket.create_connection(({address!r}, {port}), 2).close()"
    return subprocess.run(["ip", "netns", "exec", hosts.ns(host), sys_python(), "-c", code],
                          capture_output=True, timeout=30).returncode == 0


def start_master(hosts: Hosts, host: int, port: int = 11400) -> RosProcess:
    """A bare rosmaster on ``host`` (the namespace is fresh: the port is free), with ``/run_id`` set."""
    from ltl_stack.sim.session import master_command

    env = hosts.env(host, host, port)
    master = hosts.run(host, master_command(port), env, "rosmaster")
    uri = env["ROS_MASTER_URI"]

    def answers() -> bool:
        out = subprocess.run(["ip", "netns", "exec", hosts.ns(host), sys_python(), "-c",
                              f"import xmlrpc.client as x; print(x.ServerProxy({uri!r}).setParam('/t', '/run_id', "
                              f"'i32-{port}')[0])"], capture_output=True, text=True, timeout=30)
        return out.stdout.strip() == "1"

    wait_for(answers, 60, f"the rosmaster on {hosts.ns(host)}")
    return master


def sys_python() -> str:
    import sys

    return sys.executable

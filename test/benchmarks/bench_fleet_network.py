"""A fleet on a network (on demand, root, ``ip netns``): step latency across emulated hosts and the
deadman's reaction time.

    python test/benchmarks/bench_fleet_network.py [--changes 100] [--cuts 5] [--json]

Hosts are network namespaces on one bridge (``test/integration/netns_hosts.py``). Spec ``x' <-> a'``.

* Step latency: a probe on host 1 toggles input ``a`` and waits for output ``x`` to follow, one
  change at a time; the time from its publish to the output's arrival (both on host 1's clock) is a
  round trip through the executor. Configurations, in one run: the executor on host 1 itself (no
  network), on host 0 over the bridge, on host 0 behind the user-space forwarder without delay (its
  own cost), and with 50 ms each way (``lossy_forwarder.py``). Median, p95 and the ratio to the
  bridge's median.
* Deadman: ``set_velocity`` on host 1 active (cmd_vel 0.3), host 1 cut off; the time from the cut to
  its zero Twist (``~deadman`` 1 s by default). The old code never sends one (no deadman).
* The executor's CPU (user + sys, /proc) over 10 s with its input fresh, and over 10 s with it
  unknown (host 1 cut off, ``--freshness 1``).
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "test"))
sys.path.insert(0, str(ROOT / "test" / "integration"))

from helpers import SAY, wait_for  # noqa: E402
from netns_hosts import Hosts, netns_refusal, start_master  # noqa: E402

PORT = 11400
SPEC = "[INPUT]\na\n\n[OUTPUT]\nx\n\n[SYS_TRANS]\nx' <-> a'\n"
PROBE = '''
import sys, threading, time
import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import Bool

rospy.init_node("probe", disable_signals=True)
got = threading.Event()
want = [None]
arrived = [0.0]
def on_x(msg):
    if msg.data == want[0]:
        arrived[0] = time.monotonic()
        got.set()
rospy.Subscriber("/bench/outputs/x", Bool, on_x, queue_size=100, tcp_nodelay=True)
pub = rospy.Publisher("/bench/inputs/a", Bool, queue_size=10, latch=True, tcp_nodelay=True)
pub.publish(Bool(False))
want[0] = False
got.wait(120)
time.sleep(1.0)
for k in range(int(sys.argv[1])):
    value = k % 2 == 0
    got.clear()
    want[0] = value
    sent = time.monotonic()
    pub.publish(Bool(value))
    if not got.wait(30):
        print("lost", k, flush=True)
        continue
    print("rtt", arrived[0] - sent, flush=True)
print("done", flush=True)
time.sleep(3600)
'''
WORLD = SAY + '''
import time
import ltl_stack.ros  # noqa: F401
import rospy
from geometry_msgs.msg import Twist
rospy.init_node("world", disable_signals=True)
rospy.Subscriber("/bench/cmd_vel", Twist, lambda m: say("cmd", m.linear.x, time.monotonic()), queue_size=100)
rospy.spin()
'''


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def latency(workdir: Path, executor_host: int, link: tuple[float, float] | None, changes: int) -> list[float]:
    """Round trips of ``changes`` input changes from host 1 through an executor on ``executor_host``."""
    hosts = Hosts(workdir, 2)
    try:
        start_master(hosts, 0, PORT)
        if link is not None:
            hosts.make_lossy(1, link[0], link[1], 0.0)
        spec = workdir / "bench.structuredslugs"
        spec.write_text(SPEC)
        hosts.run(executor_host, ["rosrun", "ltl_stack", "controller_executor", str(spec)],
                  hosts.env(executor_host, 0, PORT), "executor")
        script = workdir / "probe.py"
        script.write_text(PROBE)
        probe = hosts.run(1, [sys.executable, str(script), str(changes)], hosts.env(1, 0, PORT), "probe")
        probe.wait_output("done", timeout=600)
        return [float(line.split()[1]) for line in probe.output().splitlines() if line.startswith("rtt ")]
    finally:
        hosts.close()


def cpu_seconds(pid: int) -> float:
    import os

    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def deadman(workdir: Path, cuts: int) -> tuple[list[float], float, float]:
    """Seconds from cutting host 1 off to its set_velocity node's zero Twist, ``cuts`` times; the
    executor's CPU seconds over 10 s with its input fresh and over 10 s with it unknown."""
    hosts = Hosts(workdir, 2)
    try:
        start_master(hosts, 0, PORT)
        spec = workdir / "bench.structuredslugs"
        spec.write_text(SPEC.replace("x' <-> a'", "x' <-> !a'"))
        executor = hosts.run(0, ["rosrun", "ltl_stack", "controller_executor", str(spec), "--freshness", "1"],
                             hosts.env(0, 0, PORT), "executor")
        env = hosts.env(1, 0, PORT)
        script = workdir / "world.py"
        script.write_text(WORLD)
        world = hosts.run(1, [sys.executable, str(script)], env, "world")
        hosts.run(1, ["rosrun", "ltl_stack", "set_velocity", "_proposition_topic:=/bench/outputs/x",
                      "_topic:=/bench/cmd_vel", "_vx:=0.3"], env, "move")
        hosts.run(1, ["rostopic", "pub", "-r", "10", "/bench/inputs/a", "std_msgs/Bool", "false"], env, "input")

        def cmds() -> list[tuple[float, float]]:
            return [(float(p[1]), float(p[2])) for p in (line.split() for line in world.output().splitlines())
                    if p and p[0] == "cmd"]

        wait_for(lambda: any(v == 0.3 for v, _ in cmds()), 120, "cmd_vel 0.3")
        start = cpu_seconds(executor.popen.pid)
        time.sleep(10)
        fresh = cpu_seconds(executor.popen.pid) - start
        hosts.cut(1)
        executor.wait_output("input(s) unknown", timeout=60)
        start = cpu_seconds(executor.popen.pid)
        time.sleep(10)
        unknown = cpu_seconds(executor.popen.pid) - start
        hosts.heal(1)
        reactions = []
        for _ in range(cuts):
            seen = len(cmds())
            wait_for(lambda n=seen: any(v == 0.3 for v, _ in cmds()[n:]), 120, "cmd_vel 0.3")
            mark = len(cmds())
            cut = time.monotonic()
            hosts.cut(1)
            wait_for(lambda n=mark: any(v == 0.0 for v, _ in cmds()[n:]), 60, "the deadman's zero Twist")
            reactions.append(next(t for v, t in cmds()[mark:] if v == 0.0) - cut)
            hosts.heal(1)
        return reactions, fresh, unknown
    finally:
        hosts.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--changes", type=int, default=100)
    parser.add_argument("--cuts", type=int, default=5)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    refusal = netns_refusal()
    if refusal is not None:
        print(f"skipped: {refusal}")
        return 0
    results: dict[str, dict[str, float]] = {}
    configs = [("same host (no network)", 1, None), ("across the bridge", 0, None),
               ("forwarder, no delay", 0, (0.0, 0.0)), ("forwarder, 50 ms each way", 0, (0.05, 0.0))]
    for name, host, link in configs:
        with tempfile.TemporaryDirectory(prefix="i32bench-") as tmp:
            rtts = latency(Path(tmp), host, link, args.changes)
        results[name] = {"n": len(rtts), "median_ms": 1000 * statistics.median(rtts),
                         "p95_ms": 1000 * percentile(rtts, 0.95)}
    base = results["across the bridge"]["median_ms"]
    for row in results.values():
        row["ratio_to_bridge"] = row["median_ms"] / base
    with tempfile.TemporaryDirectory(prefix="i32bench-") as tmp:
        reactions, fresh, unknown = deadman(Path(tmp), args.cuts)
    results["deadman (~deadman 1 s)"] = {"n": len(reactions), "median_ms": 1000 * statistics.median(reactions),
                                         "max_ms": 1000 * max(reactions)}
    results["executor CPU per 10 s"] = {"fresh_ms": 1000 * fresh, "unknown_ms": 1000 * unknown}
    if args.json:
        print(json.dumps(results, indent=2))
    else:
        for name, row in results.items():
            print(f"{name:28s} " + "  ".join(f"{k} {v:.1f}" if isinstance(v, float) else f"{k} {v}"
                                             for k, v in row.items()))
    return 0


def test_bench_fleet_network():
    assert main(["--changes", "20", "--cuts", "2"]) == 0


if __name__ == "__main__":
    sys.exit(main())

"""Cost of stopping a rospy node (on demand): ours (``import ltl_stack.ros`` first) against plain rospy.

    python test/benchmarks/bench_node_shutdown.py [--repeat 10] [--json]
    (or: python -m pytest test/benchmarks/bench_node_shutdown.py -q)

A rosmaster runs on a free loopback port. Each run starts a fresh node process (one publisher, one
subscriber), lets it register, sends it SIGINT (Ctrl-C, as roslaunch does first) and waits for it to
exit. Per run: the process's whole CPU time (user + sys, from ``wait4``) and the wall time from
SIGINT to exit. The two kinds alternate so that load drift hits both alike; the table gives medians
and the ratio ours / plain within the run. The difference is ``ltl_stack.ros.rospy_fixes``: rospy's
XML-RPC thread polls its closed socket at 100% of a core after shutdown (ros/ros_comm#2238) and its
registration thread is woken too early to notice the shutdown, which costs each node ~0.5 s.
"""
from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "test"))

NODE = """
import sys
if sys.argv[1] == "ours":
    import ltl_stack.ros  # noqa: F401
import rospy
from std_msgs.msg import Bool
rospy.init_node("shutdown_bench", anonymous=True)
publisher = rospy.Publisher("~out", Bool, queue_size=1)
subscriber = rospy.Subscriber("~in", Bool, lambda message: None)
print("ready", flush=True)
rospy.spin()
"""


def one_run(kind: str, env: dict, settle: float) -> tuple[float, float]:
    """(CPU s of the whole process, wall s from SIGINT to exit) of one node of ``kind``."""
    proc = subprocess.Popen([sys.executable, "-c", NODE, kind], env=env, stdout=subprocess.PIPE, text=True)
    try:
        if proc.stdout.readline().strip() != "ready":
            raise RuntimeError(f"the {kind} node did not start")
        time.sleep(settle)  # registration with the master done
        start = time.monotonic()
        proc.send_signal(signal.SIGINT)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.monotonic() - start
        proc.returncode = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
    finally:
        if proc.returncode is None:
            proc.kill()
            proc.wait()
        proc.stdout.close()
    return usage.ru_utime + usage.ru_stime, wall


def run(repeat: int = 10, settle: float = 1.0) -> dict:
    from helpers import RosMaster

    samples: dict[str, dict[str, list[float]]] = {k: {"cpu": [], "wall": []} for k in ("ours", "plain")}
    with tempfile.TemporaryDirectory(prefix="bench_shutdown_") as tmp:
        master = RosMaster(Path(tmp))
        try:
            for i in range(repeat):
                for kind in (("ours", "plain") if i % 2 == 0 else ("plain", "ours")):
                    cpu, wall = one_run(kind, master.env, settle)
                    samples[kind]["cpu"].append(cpu)
                    samples[kind]["wall"].append(wall)
                    print(f"[bench] run {i + 1}/{repeat} {kind}: {cpu:.3f} s CPU, exit {wall:.3f} s after SIGINT",
                          file=sys.stderr)
        finally:
            master.shutdown()
    medians = {k: {m: statistics.median(v) for m, v in s.items()} for k, s in samples.items()}
    return {"repeat": repeat, "medians": medians, "samples": samples,
            "ratio_cpu": medians["ours"]["cpu"] / medians["plain"]["cpu"],
            "ratio_wall": medians["ours"]["wall"] / medians["plain"]["wall"],
            "load_average": os.getloadavg()[0]}


def test_our_nodes_stop_at_less_cpu_than_plain_rospy():
    figures = run(repeat=5)
    assert figures["ratio_cpu"] < 1, figures["medians"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10, help="runs of each kind (default: %(default)s)")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    figures = run(args.repeat)
    if args.json:
        print(json.dumps(figures, indent=2))
        return 0
    m = figures["medians"]
    print(f"node started, registered, stopped with SIGINT; medians of {args.repeat} runs each "
          f"(load average {figures['load_average']:.1f})")
    print("| node | CPU of the whole process | SIGINT to exit |")
    print("|---|---|---|")
    for kind in ("ours", "plain"):
        print(f"| {kind} | {m[kind]['cpu'] * 1000:.0f} ms | {m[kind]['wall'] * 1000:.0f} ms |")
    print(f"| ours / plain | {figures['ratio_cpu']:.2f} | {figures['ratio_wall']:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

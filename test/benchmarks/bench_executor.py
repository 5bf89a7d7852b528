"""Executor latency (on demand): input change -> output message received, through a real master.

    python test/benchmarks/bench_executor.py [--changes 1000] [--peer-changes 300]
    (or: python -m pytest test/benchmarks/bench_executor.py -q -s)

A rosmaster runs on a free loopback port. A measuring node toggles the input ``in`` of the spec
``out' <-> in'`` and times, with the system-wide monotonic clock, from just before it publishes the
new input to the moment it receives the matching ``out`` message. Two controllers serve the spec,
in the same run and one after the other:

* ours: ``controller_executor`` (event driven, steps in the input callback);
* the thesis stack's design, reimplemented: a loop at 10 Hz reads the latest input and asks a
  controller service (``std_srvs/SetBool``: input in, output out) for each step, then publishes.
  The service server and the loop share one process; every step is still a TCPROS service call.

Both step the same synthesized strategy (``ltl_stack.synthesis.synthesize``). Figures go to
docs/benchmarks/executor.md; the goal for ours is median < 3 ms and p99 < 15 ms.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "test"))
OUT = ROOT / "docs" / "benchmarks" / "executor.md"

SPEC = textwrap.dedent("""\
    [INPUT]
    in

    [OUTPUT]
    out

    [SYS_TRANS]
    | & out' in' & ! out' ! in'

    [SYS_INIT]
    | & out in & ! out ! in
    """)

# Toggles the input, times each change until the matching output arrives; prints the latencies (s).
MEASURER = textwrap.dedent('''\
    import json, random, sys, threading, time
    import rospy
    from std_msgs.msg import Bool

    in_topic, out_topic, changes, warmup = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    max_gap = float(sys.argv[5])
    rng = random.Random(4)
    rospy.init_node("latency_probe", disable_signals=True)
    got = threading.Event()
    want = {"value": None, "t": 0.0}

    def on_out(msg):
        if msg.data == want["value"] and not got.is_set():
            want["t"] = time.monotonic()
            got.set()

    sub = rospy.Subscriber(out_topic, Bool, on_out, queue_size=10, tcp_nodelay=True)
    pub = rospy.Publisher(in_topic, Bool, queue_size=10, tcp_nodelay=True)
    deadline = time.monotonic() + 30
    while (pub.get_num_connections() < 1 or sub.get_num_connections() < 1) and time.monotonic() < deadline:
        time.sleep(0.01)
    latencies, lost = [], 0
    value = False
    for i in range(warmup + changes):
        time.sleep(rng.uniform(0.0, max_gap))  # changes arrive at random phases, not right after a receipt
        value = not value
        got.clear()
        want["value"] = value
        start = time.monotonic()
        pub.publish(Bool(value))
        if not got.wait(2.0):
            lost += 1
            continue
        if i >= warmup:
            latencies.append(want["t"] - start)
    print(json.dumps({"latencies": latencies, "lost": lost}), flush=True)
    ''')

# The thesis stack's design: a controller service stepped by a 10 Hz loop.
THESIS_PEER = textwrap.dedent('''\
    import sys, threading
    import rospy
    from std_msgs.msg import Bool
    from std_srvs.srv import SetBool, SetBoolResponse
    from ltl_stack.spec import load_spec
    from ltl_stack.synthesis import synthesize

    spec_path, ns = sys.argv[1], sys.argv[2]
    strategy = synthesize(load_spec(spec_path)).strategy
    rospy.init_node("thesis_controller")
    state = {"s": None}

    def step(request):
        inputs = {"in": request.data}
        s = state["s"]
        s = strategy.initial_state(inputs=inputs) if s is None else strategy.step(s, inputs)
        state["s"] = s
        return SetBoolResponse(success=s.outputs["out"], message=str(s.id))

    rospy.Service("~step", SetBool, step)
    latest = {"in": None}
    rospy.Subscriber(f"/{ns}/inputs/in", Bool, lambda m: latest.__setitem__("in", m.data), queue_size=10)
    out = rospy.Publisher(f"/{ns}/outputs/out", Bool, queue_size=10, latch=True)
    rospy.wait_for_service("~step")
    call = rospy.ServiceProxy("~step", SetBool)
    rate = rospy.Rate(10)
    while not rospy.is_shutdown():
        if latest["in"] is not None:
            out.publish(Bool(call(latest["in"]).success))
        rate.sleep()
    ''')


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q * (len(ordered) - 1))))]


def measure(master, workdir: Path, ns: str, changes: int, warmup: int, max_gap: float) -> dict:
    script = workdir / "measurer.py"
    script.write_text(MEASURER)
    proc = subprocess.run([sys.executable, str(script), f"/{ns}/inputs/in", f"/{ns}/outputs/out", str(changes),
                           str(warmup), str(max_gap)], env=master.env, capture_output=True, text=True,
                          timeout=changes * (2 + max_gap) + 120)
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    lat = result["latencies"]
    return {"changes": len(lat), "lost": result["lost"], "median_ms": statistics.median(lat) * 1e3,
            "p99_ms": percentile(lat, 0.99) * 1e3, "max_ms": max(lat) * 1e3, "min_ms": min(lat) * 1e3}


def step_compute_ms(spec_path: Path, n: int = 2000) -> float:
    """Median time of one Controller step in-process (no ROS), for scale."""
    from ltl_stack.runtime.executor.controller import Controller
    from ltl_stack.spec import load_spec
    from ltl_stack.synthesis import synthesize

    ctl = Controller(synthesize(load_spec(spec_path)).strategy)
    ctl.report("in", False)
    times, value = [], False
    for _ in range(n):
        value = not value
        start = time.perf_counter()
        ctl.report("in", value)
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e3


def run(changes: int = 1000, peer_changes: int = 300, write: bool = True) -> dict:
    from helpers import RosMaster

    with tempfile.TemporaryDirectory(prefix="bench_executor_") as tmp:
        workdir = Path(tmp)
        spec = workdir / "bench.slugsin"
        spec.write_text(SPEC)
        master = RosMaster(workdir)
        try:
            ours = master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), "--ready-timeout", "0",
                               "--publisher-check-period", "0"], name="executor")
            master.wait_for_subscriber("/bench/inputs/in", timeout=60)
            result_ours = measure(master, workdir, "bench", changes, warmup=20, max_gap=0.005)
            ours.stop()
            peer_script = workdir / "thesis_peer.py"
            peer_script.write_text(THESIS_PEER)
            peer = master.run([sys.executable, str(peer_script), str(spec), "bench"], name="thesis_peer")
            master.wait_for_subscriber("/bench/inputs/in", timeout=60)
            result_peer = measure(master, workdir, "bench", peer_changes, warmup=5, max_gap=0.1)
            peer.stop()
        finally:
            master.shutdown()
        compute = step_compute_ms(spec)
    figures = {"ours": result_ours, "thesis": result_peer, "step_compute_ms": compute}
    if write:
        write_report(figures, changes, peer_changes)
    return figures


def write_report(f: dict, changes: int, peer_changes: int) -> None:
    ours, peer = f["ours"], f["thesis"]
    ok = ours["median_ms"] < 3 and ours["p99_ms"] < 15
    lines = [
        "# Executor latency: input change -> output message received",
        "",
        "Command: `python test/benchmarks/bench_executor.py --changes "
        f"{changes} --peer-changes {peer_changes}` (from the repository root, after `source tools/env.sh`).",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores shared with other developers' work, so the "
        "figures were taken under load; Python "
        f"{platform.python_version()}, real rosmaster on a free loopback port, spec `out' <-> in'`.",
        "",
        "| design | changes | lost | median (ms) | p99 (ms) | max (ms) |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
        f"| ltl_stack `controller_executor` (event driven, steps in the input callback) | {ours['changes']} | "
        f"{ours['lost']} | {ours['median_ms']:.2f} | {ours['p99_ms']:.2f} | {ours['max_ms']:.2f} |",
        f"| thesis stack's design, reimplemented (10 Hz loop, one service call per step) | {peer['changes']} | "
        f"{peer['lost']} | {peer['median_ms']:.2f} | {peer['p99_ms']:.2f} | {peer['max_ms']:.2f} |",
        "",
        f"Median ratio thesis design / ours: {peer['median_ms'] / ours['median_ms']:.0f}x. "
        f"Goal (median < 3 ms, p99 < 15 ms): {'met' if ok else 'NOT met'}.",
        "",
        f"For scale, one in-process `Controller.report` step (strategy step included, no ROS) takes "
        f"{f['step_compute_ms'] * 1e3:.0f} µs (median of 2000); the rest is two TCPROS hops on loopback "
        "and the nodes' Python threads.",
        "",
        "Latency is measured from just before the probe publishes the new input value to the moment its "
        "subscriber callback sees the matching output value (system-wide monotonic clock, one process). "
        "Before each change the probe sleeps a random 0-5 ms (ours) or 0-100 ms (thesis design), so changes "
        "arrive at random phases of the 10 Hz loop; the thesis design then waits half a period (50 ms) on "
        "average for its next tick before the service call.",
        "",
    ]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    tmp = OUT.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines))
    os.replace(tmp, OUT)


def test_executor_latency():
    figures = run()
    print(json.dumps(figures, indent=2))
    assert figures["ours"]["changes"] >= 1000, figures
    assert figures["ours"]["median_ms"] < figures["thesis"]["median_ms"], figures


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--changes", type=int, default=1000)
    parser.add_argument("--peer-changes", type=int, default=300)
    parser.add_argument("--no-write", action="store_true", help="do not update docs/benchmarks/executor.md")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    figures = run(args.changes, args.peer_changes, write=not args.no_write)
    if args.json:
        print(json.dumps(figures, indent=2))
    else:
        for name in ("ours", "thesis"):
            r = figures[name]
            print(f"{name:7s} n={r['changes']:5d} lost={r['lost']} median={r['median_ms']:.2f} ms "
                  f"p99={r['p99_ms']:.2f} ms max={r['max_ms']:.2f} ms", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

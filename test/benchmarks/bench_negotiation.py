"""Integrative negotiation benchmarks (on demand): the §4.10.4 comparison for Example 13 and the
negotiation latency.

    python test/benchmarks/bench_negotiation.py [--repeat 10] [--skip-ros]

1. §4.10.4 comparison on Example 13 (config/kitchen, in process: test/unit/runtime/kitchen_world.py,
   30 ticks): base case (no recovery, no characterization), recovery only, environment
   characterization only, characterization + integrative negotiation — whether D delivers, A passes,
   C cooks, D returns, and how each ends.
2. Alg. 4 in process on the Ex. 13 specs (D blocked at the door negotiates with A): one whole
   negotiation (both offers, both phi^nego syntheses, both status exchanges), median over --repeat.
3. Through a real master: D's and A's negotiation nodes (test/integration/negotiation_party.py, the
   ``ltl_stack/Negotiate`` service) — from D starting the negotiation (its conflict detected and
   characterization failed) to both robots running their new controllers (the later of the two
   adoptions), median over --repeat fresh pairs of nodes. Goal: median < 1 s.
4. Through real ``controller_executor`` nodes: ``launch/kitchen.launch`` run --executors times; from the
   rospy log timestamps of each run, for D-A and C-A: negotiation started (after characterization
   failed) → both robots running their new controllers (the responder's "adopted the specification
   negotiated" and the initiator's "resynthesized with negotiation"), and the same from the moment
   the initiator's monitor started characterizing (conflict detected after the 1 s threshold). Goal: median < 1 s.

5. ``--signing``: signed vs unsigned messages (a fleet secret, ``runtime.resilience.negotiation.auth``), in the same
   run, interleaved: Alg. 4 in process with every message signed and checked on both sides, and through
   a real master with both nodes' mappings naming the secret. Medians and their ratio; figures go to
   docs/benchmarks/negotiation_signing.md (the rest of the file is not rerun).

Figures go to docs/benchmarks/negotiation.md.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "test"))
sys.path.insert(0, str(ROOT / "test" / "unit" / "runtime"))
OUT = ROOT / "docs" / "benchmarks" / "negotiation.md"
PARTY = ROOT / "test" / "integration" / "negotiation_party.py"
KITCHEN = ROOT / "config" / "kitchen"

from helpers import RosMaster, wait_for  # noqa: E402
from kitchen_world import KitchenWorld  # noqa: E402

from ltl_stack.runtime.config.mapping import load_mapping  # noqa: E402
from ltl_stack.runtime.resilience.negotiation import Negotiation, answer, classes_from_mapping, drive  # noqa: E402
from ltl_stack.spec import load_spec  # noqa: E402

REGIONS = ["company", "road", "storage", "prepArea", "cookingArea"]
D_BLOCKED_IN = {**{f"{r}_c": r == "road" for r in REGIONS}, "pickup_c": False, "deliver_c": False, "order": False,
                "openDoor_A": False, "prepArea_c_A": True, "cookingArea_c_C": True}
D_BLOCKED_OUT = {**{r: r == "road" for r in REGIONS}, "pickup": False, "deliver": False, "orderReceived": True}
A_IN = {"prepArea_c": True, "cookingArea_c_C": True, "company_c_D": True}


def comparison() -> list[str]:
    rows = ["| approach | D delivers | A passes | C cooks | D back in company | at the end |", "|---|---|---|---|---|---|"]
    names = {"base": "base case", "recovery": "recovery only", "ec": "characterization (EC) only",
             "negotiation": "EC + integrative negotiation"}
    for mode in ("base", "recovery", "ec", "negotiation"):
        world = KitchenWorld(mode)
        world.run(30)
        s = world.summary()
        d = world.strategies["D"]
        if mode == "base":
            end = f"D's controller has no next state in road: a violation at each of {sum('D' in h['raised'] for h in world.history)} ticks"
        elif mode == "recovery":
            end = f"D waits in front of the door ({d.counters.recovery_steps} recovery steps)"
        elif mode == "ec":
            end = (f"D: {d.counters.ec1 + d.counters.ec2} resynthesis, then unrealizable: waiting for the user "
                   f"({d.mode.value})")
        else:
            end = "; ".join(f"{n['session']} {n['case']}" for n in s["negotiations"]) + "; every robot normal"
        at = {k: (f"tick {s[k]}" if s[k] is not None else "no") for k in ("delivered", "passed", "cooked", "back_in_company")}
        rows.append(f"| {names[mode]} | {at['delivered']} | {at['passed']} | {at['cooked']} | {at['back_in_company']} | {end} |")
    return rows


def in_process(repeat: int) -> float:
    d_spec = load_spec(KITCHEN / "delivery_agent.structuredslugs")
    a_spec = load_spec(KITCHEN / "kitchen_assistant.structuredslugs")
    d_classes = classes_from_mapping(load_mapping(KITCHEN / "delivery_agent.yaml"))
    a_classes = classes_from_mapping(load_mapping(KITCHEN / "kitchen_assistant.yaml"))
    a_in = {**dict.fromkeys(a_spec.inputs, False), **A_IN}
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        d = Negotiation(d_spec, d_classes, "A", incoming=D_BLOCKED_IN, outputs=D_BLOCKED_OUT)
        a = Negotiation(a_spec, a_classes, "D", incoming=a_in, outputs={**dict.fromkeys(a_spec.outputs, False), "prepArea": True},
                        initiator=False)
        drive(d, lambda m, a=a: answer(a, m))
        times.append(time.perf_counter() - start)
        assert d.outcome.name == a.outcome.name == "BOTH_ADOPT", (d.report(), a.report())
    return statistics.median(times)


def in_process_pair(signed: bool) -> float:
    """One whole Alg. 4 negotiation in process (see ``in_process``), every message signed by its sender
    and checked by its receiver when ``signed``: seconds."""
    from ltl_stack.runtime.resilience.negotiation.auth import Authenticator

    d_spec = load_spec(KITCHEN / "delivery_agent.structuredslugs")
    a_spec = load_spec(KITCHEN / "kitchen_assistant.structuredslugs")
    d_classes = classes_from_mapping(load_mapping(KITCHEN / "delivery_agent.yaml"))
    a_classes = classes_from_mapping(load_mapping(KITCHEN / "kitchen_assistant.yaml"))
    a_in = {**dict.fromkeys(a_spec.inputs, False), **A_IN}
    secret = b"a fleet secret for the benchmark, 32+ bytes"
    d_auth, a_auth = Authenticator("D", {"A": secret}), Authenticator("A", {"D": secret})
    start = time.perf_counter()
    d = Negotiation(d_spec, d_classes, "A", incoming=D_BLOCKED_IN, outputs=D_BLOCKED_OUT)
    a = Negotiation(a_spec, a_classes, "D", incoming=a_in,
                    outputs={**dict.fromkeys(a_spec.outputs, False), "prepArea": True}, initiator=False)

    def call(message):
        if not signed:
            return answer(a, message)
        message = d_auth.sign(message, "A")
        assert a_auth.check(message) is None
        reply = a_auth.sign(answer(a, message), "D", reply_to=message.nonce)
        assert d_auth.check(reply, reply_to=message.nonce, sender="A") is None
        return reply

    drive(d, call)
    elapsed = time.perf_counter() - start
    assert d.outcome.name == a.outcome.name == "BOTH_ADOPT", (d.report(), a.report())
    return elapsed


def signing(repeat: int, skip_ros: bool) -> list[str]:
    """Signed vs unsigned (module docstring, 5.): table rows."""
    runs: dict[bool, list[float]] = {False: [], True: []}
    for _ in range(repeat):
        for signed in (False, True):  # interleaved: the machine's load falls on both alike
            runs[signed].append(in_process_pair(signed))
    rows = ["| what | unsigned median | signed median | signed / unsigned | runs |", "|---|---|---|---|---|"]

    def row(what: str, values: dict[bool, list[float]]) -> str:
        plain, signed = statistics.median(values[False]), statistics.median(values[True])
        return (f"| {what} | {plain * 1000:.1f} ms | {signed * 1000:.1f} ms | {signed / plain:.2f} | "
                f"{len(values[True])} each |")

    rows.append(row("Alg. 4 in process, D–A (every message signed and checked on both sides)", runs))
    if not skip_ros:
        rows.append(row("through a real master: D starts → both running their new controllers",
                        through_master_signing(repeat)))
    return rows


def through_master_signing(repeat: int) -> dict[bool, list[float]]:
    found: dict[bool, list[float]] = {False: [], True: []}
    with tempfile.TemporaryDirectory() as tmp:
        key = Path(tmp) / "fleet.key"
        key.write_bytes(b"a fleet secret for the benchmark, 32+ bytes")
        key.chmod(0o600)
        mappings = {}
        for name in ("kitchen_assistant", "delivery_agent"):
            text = (KITCHEN / f"{name}.yaml").read_text()
            signed = Path(tmp) / f"{name}.yaml"
            signed.write_text(text.replace("negotiation:\n", f"negotiation:\n  secret_file: {key}\n", 1))
            mappings[name] = {False: KITCHEN / f"{name}.yaml", True: signed}
        master = RosMaster(Path(tmp))
        os.environ.update({k: master.env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME")})
        try:
            for k in range(repeat):
                for signed in (False, True):
                    a = master.run([sys.executable, str(PARTY), "responder",
                                    str(KITCHEN / "kitchen_assistant.structuredslugs"),
                                    str(mappings["kitchen_assistant"][signed]), "--inputs", json.dumps(A_IN),
                                    "__ns:=/kitchen/A"], name=f"A{k}{signed}")
                    a.wait_output('"ready"', timeout=60)
                    d = master.run([sys.executable, str(PARTY), "initiator",
                                    str(KITCHEN / "delivery_agent.structuredslugs"),
                                    str(mappings["delivery_agent"][signed]), "--peer", "A", "--inputs",
                                    json.dumps(D_BLOCKED_IN), "--outputs", json.dumps(D_BLOCKED_OUT),
                                    "__ns:=/kitchen/D"], name=f"D{k}{signed}")
                    wait_for(lambda a=a, d=d: reports(a) and reports(d), 60, "both reports")
                    rd, ra = reports(d)[-1], reports(a)[-1]
                    assert rd["case"] == ra["case"] == "BOTH_ADOPT", (d.output(), a.output())
                    found[signed].append(max(rd["finished"], ra["finished"]) - rd["started"])
                    a.stop()
                    d.stop()
        finally:
            master.shutdown()
    return found


def reports(proc) -> list[dict]:
    return [json.loads(x)["report"] for x in proc.output().splitlines() if x.startswith('{"report"')]


def through_master(repeat: int) -> list[float]:
    latencies = []
    with tempfile.TemporaryDirectory() as tmp:
        master = RosMaster(Path(tmp))
        os.environ.update({k: master.env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR", "ROS_HOME")})
        try:
            for k in range(repeat):
                a = master.run([sys.executable, str(PARTY), "responder", str(KITCHEN / "kitchen_assistant.structuredslugs"),
                                str(KITCHEN / "kitchen_assistant.yaml"), "--inputs", json.dumps(A_IN),
                                "__ns:=/kitchen/A"], name=f"A{k}")
                a.wait_output('"ready"', timeout=60)
                d = master.run([sys.executable, str(PARTY), "initiator", str(KITCHEN / "delivery_agent.structuredslugs"),
                                str(KITCHEN / "delivery_agent.yaml"), "--peer", "A", "--inputs", json.dumps(D_BLOCKED_IN),
                                "--outputs", json.dumps(D_BLOCKED_OUT), "__ns:=/kitchen/D"], name=f"D{k}")
                wait_for(lambda a=a, d=d: reports(a) and reports(d), 60, "both reports")
                rd, ra = reports(d)[0], reports(a)[0]
                assert rd["case"] == ra["case"] == "BOTH_ADOPT", (d.output(), a.output())
                latencies.append(max(rd["finished"], ra["finished"]) - rd["started"])
                a.stop()
                d.stop()
        finally:
            master.shutdown()
    return latencies


def stamps(log: str, text: str) -> list[float]:
    return [float(line.split("[", 3)[2].split("]")[0]) for line in log.splitlines()
            if text in line and line.startswith("[")]


def through_executors(runs: int) -> dict[str, list[float]]:
    """Example 13 on real executors (see the module docstring, 4.)."""
    found: dict[str, list[float]] = {"D-A": [], "C-A": [], "D-A from detection": [], "C-A from detection": []}
    with tempfile.TemporaryDirectory() as tmp:
        master = RosMaster(Path(tmp))
        try:
            for k in range(runs):
                out = Path(tmp) / f"run{k}"
                out.mkdir()
                launch = master.run(["roslaunch", "ltl_stack", "kitchen.launch", f"out:={out}"], name=f"kitchen{k}")
                launch.wait_output("kitchen_world: C cooked the ingredients", timeout=180)
                log = launch.output()
                launch.stop()
                adopted = stamps(log, "/kitchen/A/controller_executor: [normal] adopted the specification negotiated")
                for pair, robot, index in (("D-A", "D", 0), ("C-A", "C", 1)):
                    ex = f"/kitchen/{robot}/controller_executor:"
                    start = stamps(log, f"{ex} negotiation {robot}->A: starting with A")[0]
                    detect = [t for t in stamps(log, f"{ex} [characterizing] characterizing after") if t <= start][-1]
                    running = max(adopted[index], stamps(log, f"{ex} [normal] resynthesized with negotiation")[0])
                    found[pair].append(running - start)
                    found[f"{pair} from detection"].append(running - detect)
        finally:
            master.shutdown()
    return found


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10)
    parser.add_argument("--executors", type=int, default=5, help="kitchen.launch runs (0: skip)")
    parser.add_argument("--skip-ros", action="store_true")
    parser.add_argument("--signing", action="store_true", help="only signed vs unsigned (5.)")
    args = parser.parse_args()
    if args.signing:
        rows = signing(args.repeat, args.skip_ros)
        text = "\n".join(["# Negotiation latency, signed vs unsigned messages", "",
                          f"`python test/benchmarks/bench_negotiation.py --signing --repeat {args.repeat}` on "
                          f"{platform.node()} ({os.cpu_count()} CPUs, shared with other work), "
                          f"{time.strftime('%Y-%m-%d')}.", "", *rows, ""])
        print(text)
        (OUT.parent / "negotiation_signing.md").write_text(text)
        return 0
    lines = ["# Integrative negotiation (thesis §4.8, §4.10.3-4.10.4): figures",
             "", f"`python test/benchmarks/bench_negotiation.py --repeat {args.repeat}` on {platform.node()} "
             f"({os.cpu_count()} CPUs, shared with other work), {time.strftime('%Y-%m-%d')}.", "",
             "## §4.10.4 comparison, Example 13 (30 ticks, in process)", "", *comparison(), ""]
    print("\n".join(lines))
    median = in_process(args.repeat)
    lines += ["## Latency", "", "| what | median | runs |", "|---|---|---|",
              f"| Alg. 4 in process, D blocked at the door with A (2 offers, 2 syntheses, 2 status exchanges) | "
              f"{median * 1000:.0f} ms | {args.repeat} |"]
    if not args.skip_ros:
        lat = through_master(args.repeat)
        lines.append(f"| through a real master (`~negotiate` services of two nodes): D starts negotiating → both "
                     f"running their new controllers | {statistics.median(lat) * 1000:.0f} ms (min {min(lat) * 1000:.0f}, "
                     f"max {max(lat) * 1000:.0f}) | {len(lat)} |")
    if not args.skip_ros and args.executors > 0:
        found = through_executors(args.executors)
        for what, values in found.items():
            start = "characterization started (conflict detected)" if "detection" in what else "negotiation started"
            lines.append(f"| kitchen.launch, real executors, {what[:3]}: {start} → both running their new controllers | "
                         f"{statistics.median(values) * 1000:.0f} ms (min {min(values) * 1000:.0f}, max "
                         f"{max(values) * 1000:.0f}) | {len(values)} |")
    lines.append("")
    print("\n".join(lines[-8:]))
    OUT.write_text("\n".join(lines))
    print(f"written to {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

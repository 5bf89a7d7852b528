"""Resilience benchmarks (on demand): resynthesis latency and explicit recovery export.

    python test/benchmarks/bench_resilience.py [--repeat 15] [--slugs PATH] [--only ec|export]
    python test/benchmarks/bench_resilience.py --through-master [--repeat 10]

1. Environment characterization (thesis Alg. 2) in process on the Ex. 11 and Ex. 12 specs: the
   time of one ``Characterizer.characterize`` call — EC1 (and EC2 when EC1 is unrealizable) spec text
   rendered, parsed back and synthesized — for the observations of the narratives (the broken door in
   road; the alarm with a spill). Median over ``--repeat`` calls, each on a fresh Characterizer.
   Goal: median < 100 ms.
2. ``explicit(recovery=True)`` on thesis Ex. 8, firefighting, two_customer_waiter and
   error_resilience A/B (``../shared/specs``, slugs' default init, not cooperative): wall and CPU
   time of the export alone, states and edges; then, as whole processes in the same run, alternating,
   medians of ``--export-repeat``: ``synthesize SPEC --recovery --no-robotics-semantics
   --no-cooperative --slugs-json OUT`` against ``slugs --explicitStrategy --simpleRecovery
   --jsonOutput SPEC OUT`` (``--slugs PATH``; skipped without it; ``--slugs-timeout``, 120 s; a run
   that timed out is not repeated). Goal: each under 5 s, >= 10x faster than slugs where it finishes.

3. ``--through-master`` (only this one then): violation -> new strategy running, through a real master.
   A fresh ``controller_executor --characterize`` per repeat (resynthesis at the first violation, in
   its worker thread) on the Ex. 11 and Ex. 12 specs and the issue's probe. A measuring node plays
   every input topic: the initial inputs, admissible preparation changes, then one input change that
   breaks the env safety (the case names it; chosen in process beforehand so that characterization
   is realizable). It times, with the monotonic clock, from just before that publish to the ``~state``
   message whose ``resyntheses`` counter went up (the new strategy installed and stepped), and to the
   first ``~state`` naming the violated clauses (the recovery move while the synthesizer works). The
   same change in process (``BackgroundResilience`` + ``Controller``, the job run inline) for scale.
   Goal: median < 300 ms through the master. Figures go to docs/benchmarks/resilience_master.md.

Figures go to docs/benchmarks/resilience.md.
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
SHARED = ROOT.parent / "shared"  # the project's shared folder, beside the repository
OUT = ROOT / "docs" / "benchmarks" / "resilience.md"
OUT_MASTER = ROOT / "docs" / "benchmarks" / "resilience_master.md"
sys.path.insert(0, str(ROOT / "test"))

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_explicit import HEADER, measure, row  # noqa: E402

from ltl_stack.runtime.resilience.characterize import Characterizer, Observation  # noqa: E402
from ltl_stack.spec import load_spec  # noqa: E402
from ltl_stack.synthesis import synthesize  # noqa: E402

EC_CASES = [
    ("Ex. 11 (alice): broken door in road", ROOT / "config" / "alice" / "alice.structuredslugs",
     {"company_c": True, "road_c": False, "storage_c": False, "doorOpen": False, "doorBroken": True, "order": True},
     {"company": False, "road": True, "storage": False},
     {"company_c": False, "road_c": True, "storage_c": False, "doorOpen": False, "doorBroken": True, "order": True}),
    ("Ex. 12 (patrol_recycling): alarm with a spill", ROOT / "config" / "patrol_recycling" / "patrol_recycling.structuredslugs",
     {"office_c": False, "entrance_c": False, "metal_deposit_c": True, "paper_deposit_c": False, "glass_deposit_c": False,
      "alarm": False, "spill": False, "tap": False, "metal": False, "glass": False, "paper": False},
     {"office": False, "entrance": False, "metal_deposit": True, "paper_deposit": False, "glass_deposit": False,
      "notify": False, "callHelp": False, "stop": False, "carryMetal": False, "carryGlass": False, "carryPaper": False},
     {"office_c": False, "entrance_c": False, "metal_deposit_c": True, "paper_deposit_c": False, "glass_deposit_c": False,
      "alarm": True, "spill": True, "tap": False, "metal": False, "glass": False, "paper": False}),
]

EXPORT_CASES = [
    ("thesis Ex. 8 (move_group_and_move_base)", "move_group_and_move_base/move_group_and_move_base.slugsin",
     "does not finish in 120 s (113-166 s in longer runs)"),
    ("firefighting", "firefighting/firefighting.slugsin", "> 120 s"),
    ("two_customer_waiter_txt", "benchmarks/slugsin/two_customer_waiter_txt.slugsin", "19.6 s (7,032 states)"),
    ("error_resilience_exampleA", "benchmarks/slugsin/error_resilience_exampleA.slugsin", "2.2 s (538 states)"),
    ("error_resilience_exampleB", "benchmarks/slugsin/error_resilience_exampleB.slugsin", "6.2 s (1,226 states)"),
]


def bench_ec(repeat: int) -> list[str]:
    rows = []
    for name, path, now, outputs, incoming in EC_CASES:
        spec = load_spec(path)
        times, cpus, variants = [], [], set()
        for k in range(repeat):
            ch = Characterizer(spec)
            start, cpu = time.perf_counter(), time.process_time()
            attempt = ch.characterize(Observation(k, time.time(), now, outputs, incoming))
            times.append(time.perf_counter() - start)
            cpus.append(time.process_time() - cpu)
            variants.add(f"{attempt.variant} {'realizable' if attempt.realizable else 'unrealizable'}")
        rows.append(f"| {name} | {statistics.median(times) * 1000:.1f} ms ({statistics.median(cpus) * 1000:.1f} ms CPU)"
                    f" | {min(times) * 1000:.1f}–{max(times) * 1000:.1f} ms | {', '.join(sorted(variants))} |")
        print(rows[-1], flush=True)
    return rows


def bench_export() -> list[str]:
    rows = []
    for name, rel, slugs in EXPORT_CASES:
        path = SHARED / "specs" / rel
        if not path.exists():
            rows.append(f"| {name} | (missing {path}) | | | | |")
            continue
        spec = load_spec(path)
        result = synthesize(spec, robotics_semantics=False, cooperative=False)
        wall, cpu = time.perf_counter(), time.process_time()
        automaton = result.strategy.explicit(recovery=True, max_states=2_000_000)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        edges = sum(len(s.successors) for s in automaton.states)
        marked = sum(len(s.recovery) for s in automaton.states)
        plain = automaton.metadata["states_without_recovery"]
        rows.append(f"| {name} | {wall:.2f} s ({cpu:.2f} s CPU) | {plain:,} / {len(automaton):,} | "
                    f"{edges:,} ({marked:,} recovery) | {slugs} |")
        print(rows[-1], flush=True)
    return rows


# --- 3. violation -> new strategy running, through a real master ---------------------------------------
PROBE_SPEC = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\n\n[ENV_INIT]\ndoor\n\n[ENV_TRANS]\ndoor'\n\n" \
             "[SYS_TRANS]\nperson' -> stop'\n"

# (name, spec file or text, preparation changes, inputs to try breaking first)
MASTER_CASES = [
    ("Ex. 11 (alice)", ROOT / "config" / "alice" / "alice.structuredslugs", [("order", True)],
     ["doorOpen", "storage_c", "road_c"]),
    ("Ex. 12 (patrol_recycling)", ROOT / "config" / "patrol_recycling" / "patrol_recycling.structuredslugs",
     [("alarm", True)], ["spill", "tap"]),
    ("issue probe (door/person)", PROBE_SPEC, [("person", True)], ["door"]),
]

# Plays the inputs, times the violating change until ~state reports the resynthesis (prints JSON).
MEASURER = textwrap.dedent('''\
    import json, sys, threading, time
    import rospy
    from std_msgs.msg import Bool
    from ltl_stack.msg import ControllerState

    plan = json.loads(sys.argv[1])
    rospy.init_node("resilience_probe", disable_signals=True)
    cond = threading.Condition()
    states = []

    def on_state(msg):
        with cond:
            states.append((time.monotonic(), msg.state_id, dict(zip(msg.inputs.keys, msg.inputs.values)),
                           msg.resyntheses, list(msg.violated_clauses), msg.mode))
            cond.notify_all()

    rospy.Subscriber(plan["state"], ControllerState, on_state, queue_size=1000, tcp_nodelay=True)
    pubs = {p: rospy.Publisher(f"{plan['ns']}/inputs/{p}", Bool, queue_size=10, latch=True, tcp_nodelay=True)
            for p in plan["init"]}
    deadline = time.monotonic() + 60
    while any(pub.get_num_connections() < 1 for pub in pubs.values()) and time.monotonic() < deadline:
        time.sleep(0.01)

    def wait(pred, timeout=60):
        end = time.monotonic() + timeout
        with cond:
            while True:
                hit = [s for s in states if pred(s)]
                if hit:
                    return hit[0]
                left = end - time.monotonic()
                if left <= 0:
                    raise SystemExit(f"timed out; last states: {states[-3:]}")
                cond.wait(left)

    readings = dict(plan["init"])
    for p, v in readings.items():
        pubs[p].publish(Bool(v))
    wait(lambda s: s[1] >= 0 and all(bool(s[2].get(p)) == v for p, v in readings.items()))
    for p, v in plan["prepare"]:
        readings[p] = v
        pubs[p].publish(Bool(v))
        wait(lambda s: s[1] >= 0 and all(bool(s[2].get(q)) == w for q, w in readings.items()))
    time.sleep(0.5)  # let it settle
    p, v = plan["flip"]
    with cond:
        seen = len(states)
    start = time.monotonic()
    pubs[p].publish(Bool(v))
    first = wait(lambda s: states.index(s) >= seen and s[4])
    done = wait(lambda s: states.index(s) >= seen and s[3] >= 1)
    print(json.dumps({"resynthesis": done[0] - start, "recovery": first[0] - start, "mode": done[5]}), flush=True)
    ''')


def _spec_of(source) -> tuple[object, str]:
    from ltl_stack.spec import parse_structured

    if isinstance(source, Path):
        return load_spec(source), source.read_text()
    return parse_structured(source, "probe.structuredslugs"), source


def plan_case(source, prepare: list, preferred: list) -> dict:
    """In process: the initial inputs, the preparation, and the first input change (preferred ones
    first) that breaks env safety and is characterized into a realizable spec; its in-process time."""
    from ltl_stack.runtime.executor.controller import Controller
    from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience

    spec, _ = _spec_of(source)
    for name in [*preferred, *spec.inputs]:
        jobs: list = []
        rs = BackgroundResilience(spec, lock=None, runner=jobs.append)
        controller = Controller(rs)
        rs.lock = controller.lock
        rs.on_installed = controller.restart_from
        init = dict(rs.strategy.initial_state().inputs)
        controller.report_many(init)
        for p, v in prepare:
            controller.report_many({p: v})
        if rs.violated_now or jobs:
            raise SystemExit(f"{spec.source}: the preparation {prepare} already breaks env safety")
        readings = {**controller.readings}
        flipped = {**readings, name: not readings[name]}
        if not rs.strategy.game.violated("env_safety", controller.state.valuation, flipped):
            continue
        start = time.perf_counter()
        controller.report_many({name: flipped[name]})
        while jobs:
            jobs.pop(0)()
        seconds = time.perf_counter() - start
        if rs.counters.resyntheses == 1:
            return {"init": init, "prepare": prepare, "flip": [name, flipped[name]], "in_process": seconds,
                    "variant": rs.characterizer.history[-1].variant}
    raise SystemExit(f"{spec.source}: no single input change breaks env safety with a realizable characterization")


def bench_master(repeat: int) -> list[str]:
    from helpers import RosMaster

    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_resilience_") as tmp:
        workdir = Path(tmp)
        measurer = workdir / "measurer.py"
        measurer.write_text(MEASURER)
        master = RosMaster(workdir)
        try:
            for name, source, prepare, preferred in MASTER_CASES:
                plan = plan_case(source, prepare, preferred)
                _, text = _spec_of(source)
                spec_path = workdir / (source.name if isinstance(source, Path) else "probe.structuredslugs")
                spec_path.write_text(text)
                ns = "/" + spec_path.stem
                times, recoveries, modes = [], [], set()
                for _ in range(repeat):
                    node = master.run(["rosrun", "ltl_stack", "controller_executor", str(spec_path), "--characterize",
                                       "--violation-grace", "0", "--ready-timeout", "0",
                                       "--publisher-check-period", "0"], name="executor")
                    try:
                        for p in plan["init"]:
                            master.wait_for_subscriber(f"{ns}/inputs/{p}", timeout=120)
                        args = {"state": "/controller_executor/state", "ns": ns, **plan}
                        done = subprocess.run([sys.executable, str(measurer), json.dumps(args)], env=master.env,
                                              capture_output=True, text=True, timeout=300)
                        if done.returncode != 0:
                            raise SystemExit(f"{name}: {done.stderr[-2000:]}\n{node.output()[-2000:]}")
                        result = json.loads(done.stdout.strip().splitlines()[-1])
                    finally:
                        node.stop()
                    times.append(result["resynthesis"])
                    recoveries.append(result["recovery"])
                    modes.add(result["mode"])
                flip = f"{plan['flip'][0]}={int(plan['flip'][1])}"
                rows.append(f"| {name} | {flip} ({plan['variant']}) | {statistics.median(times) * 1000:.0f} ms | "
                            f"{min(times) * 1000:.0f}–{max(times) * 1000:.0f} ms | "
                            f"{statistics.median(recoveries) * 1000:.1f} ms | {plan['in_process'] * 1000:.0f} ms | "
                            f"{', '.join(sorted(modes))} |")
                print(rows[-1], flush=True)
        finally:
            master.shutdown()
    return rows


def main_master(repeat: int) -> int:
    rows = bench_master(repeat)
    load = os.getloadavg()[0]
    text = "\n".join([
        "# Resilience through a real master: violation -> new strategy running",
        "",
        f"`python test/benchmarks/bench_resilience.py --through-master --repeat {repeat}` on {platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}, {time.strftime('%Y-%m-%d')}, load average "
        f"{load:.1f} at the end (machine shared with other work).",
        "",
        "A fresh `controller_executor --characterize` per repeat (characterization at the first violation, "
        "resynthesis in its worker thread); a measuring node plays the input topics and times from just before it "
        "publishes the violating change to the `~state` message whose `resyntheses` went up (new strategy "
        "installed and stepped). *recovery move*: to the first `~state` naming the violated clause (the safe "
        "move published while the synthesizer works). *in process*: the same change through `Controller` + "
        "`BackgroundResilience` with the job run inline (render, parse, synthesize EC1, and EC2 if needed, "
        "install). Goal: median < 300 ms.",
        "",
        "| spec | violating change (variant) | median | range | recovery move (median) | in process | mode after |",
        "|---|---|---|---|---|---|---|",
        *rows,
        "",
    ])
    OUT_MASTER.write_text(text)
    print(f"written {OUT_MASTER}")
    return 0


def bench_export_vs_slugs(slugs: str | None, repeat: int, timeout: float) -> list[str]:
    """Whole processes, ours and slugs alternating (``bench_explicit.measure``)."""
    rows = []
    print("\n".join(HEADER), flush=True)
    for name, rel, _ in EXPORT_CASES:
        path = SHARED / "specs" / rel
        if path.exists():
            rows.append(row(name, measure(path, slugs, repeat, timeout, ["--recovery"], ["--simpleRecovery"]),
                            slugs, timeout))
            print(rows[-1], flush=True)
    return rows


def _section(text: str, heading: str) -> list[str]:
    """The lines of the section of ``text`` whose heading starts with ``heading`` (kept from an earlier run)."""
    lines = text.splitlines()
    start = next((k for k, line in enumerate(lines) if line.startswith(heading)), None)
    if start is None:
        return []
    end = next((k for k in range(start + 1, len(lines)) if lines[k].startswith("## ")), len(lines))
    return lines[start:end]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--through-master", action="store_true",
                        help="only the violation -> new strategy benchmark through a real master")
    parser.add_argument("--only", choices=["ec", "export"], help="run one part (the page keeps the other's figures)")
    parser.add_argument("--slugs", help="path of the slugs binary (the slugs columns are skipped without it)")
    parser.add_argument("--export-repeat", type=int, default=3)
    parser.add_argument("--slugs-timeout", type=float, default=120.0)
    args = parser.parse_args(argv)
    if args.through_master:
        return main_master(args.repeat)
    slugs = args.slugs if args.slugs and Path(args.slugs).exists() else None
    old = OUT.read_text() if OUT.exists() else ""
    when = (f"on {platform.machine()}, Python {platform.python_version()}, {time.strftime('%Y-%m-%d %H:%M')} "
            "(machine shared with other work: times drift up to 2x; CPU time is the steadier figure).")
    if args.only == "export":
        ec = _section(old, "## Environment characterization")
    else:
        ec = ["## Environment characterization (Alg. 2), in process", "",
              f"`python test/benchmarks/bench_resilience.py --only ec --repeat {args.repeat}` {when}", "",
              "| observation | median (wall, CPU) | range (wall) | outcome |", "|---|---|---|---|",
              *bench_ec(args.repeat)]
    if args.only == "ec":
        export = _section(old, "## Explicit export")
    else:
        export = ["## Explicit export with recovery transitions", "",
                  f"`python test/benchmarks/bench_resilience.py --only export --slugs SLUGS --export-repeat "
                  f"{args.export_repeat}` {when}", "",
                  "In process, the export alone (slugs' default init semantics, not cooperative):", "",
                  "| spec | export time | states without / with recovery | edges | slugs `--simpleRecovery` "
                  "(reference figures, whole process) |", "|---|---|---|---|---|",
                  *bench_export(), "",
                  "Whole processes in the same run, alternating, medians (ours `synthesize SPEC --recovery "
                  "--no-robotics-semantics --no-cooperative --slugs-json OUT`; slugs `--explicitStrategy "
                  "--simpleRecovery --jsonOutput`, which adds recovery edges into W only; slugs' limit "
                  f"{args.slugs_timeout:.0f} s, a run that timed out is not repeated):", "",
                  *bench_export_vs_slugs(slugs, args.export_repeat, args.slugs_timeout)]
    text = "\n".join(["# Resilience benchmarks", "", *ec, "", *export, ""])
    OUT.write_text(text)
    print(f"written {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

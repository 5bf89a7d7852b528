"""Resilient execution under a violation flood (on demand): memory and step latency.

    python test/benchmarks/bench_flood.py [--seconds 60] [--rate 200] [--inputs 9] [--trace]

In process, as the executor node runs it (``build_strategy`` + ``make_controller`` with
``--characterize``: recovery moves meanwhile, each resynthesis in a worker thread, the new strategy
installed under the controller's lock with ``restart_from``): a spec of 9 inputs whose environment
promises ``!i0'``, driven at ``--rate`` Hz for ``--seconds`` by random input valuations, half of them
violating it. Every new violating valuation is learned (EC1) and resynthesized, so hundreds of
resyntheses happen (``--inputs 6``: at most 2^5 violating valuations, about 28 resyntheses, the
issue's condition). Measured per configuration, each in a fresh process: RSS at the start (after the
first strategy) and its peak (``/proc/self/statm`` every 0.1 s), the latency of every input step
(``Controller.report_many``, lock wait included), the resyntheses. The peers, in the same run: the same
flood as at c79dacd (glibc's mmap threshold left to adjust itself, every EC literal a new object) and
with ``Characterizer.history`` unbounded as well (as before memory was bounded). Goal: peak RSS growth < 20 MB,
step latency p99 < 100 ms. ``--trace`` runs this branch's flood alone with tracemalloc and object
counts and prints what grew (slower: not for the latency figures).
"""
from __future__ import annotations

import argparse
import collections
import ctypes
import gc
import json
import os
import random
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = ("this branch", "c79dacd", "unbounded history")


def spec_text(inputs: list[str]) -> str:
    return ("[INPUT]\n" + "\n".join(inputs) + "\n\n[OUTPUT]\nstop\ngo\n\n[ENV_INIT]\n!i0\n\n[SYS_INIT]\n!go\n\n"
            "[ENV_TRANS]\n!i0'\n\n[SYS_TRANS]\ni1' -> stop'\ngo' -> !stop'\n\n[SYS_LIVENESS]\ngo | i1\n")


def rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def mallinfo_mb() -> dict[str, float]:
    """glibc's heap: in use (``uordblks``), free but kept (``fordblks``), mmapped (``hblkhd``), arenas."""
    class Info(ctypes.Structure):
        _fields_ = [(n, ctypes.c_size_t) for n in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                                                   "fsmblks", "uordblks", "fordblks", "keepcost")]
    libc = ctypes.CDLL("libc.so.6")
    libc.mallinfo2.restype = Info
    info = libc.mallinfo2()
    return {"heap": round(info.arena / 2**20, 1), "used": round(info.uordblks / 2**20, 1),
            "free_kept": round(info.fordblks / 2**20, 1), "mmapped": round(info.hblkhd / 2**20, 1)}


def census(strategy) -> dict:
    """Objgraph-style: live objects by type, and what the characterizer and the BDD managers hold."""
    gc.collect()
    types = collections.Counter(type(o).__name__ for o in gc.get_objects())
    managers = [o for o in gc.get_objects() if type(o).__name__ == "BDD" and type(o).__module__ == "dd.cudd"]
    ch = strategy.characterizer
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # dd 0.5.7 says "mem" is in bytes now
        cudd = sum(m.statistics()["mem"] for m in managers)
    return {"types": types, "managers": len(managers), "cudd_mb": round(cudd / 2**20, 1),
            "ec1": len(ch.ec1), "ec2": len(ch.ec2), "history": len(ch.history), "events": len(strategy.events),
            "malloc": mallinfo_mb(), "rss": round(rss_mb(), 1)}


def traced(census_start: dict, census_end: dict, snap_start, snap_end) -> str:
    """What grew between the two snapshots: Python allocations by line, object counts by type."""
    lines = ["tracemalloc, top growth by line:"]
    for stat in snap_end.compare_to(snap_start, "lineno")[:12]:
        lines.append(f"  {stat.size_diff / 2**20:+.2f} MB {stat.count_diff:+d} blocks {stat.traceback}")
    grown = census_end["types"] - census_start["types"]
    lines.append("object types, top growth: " + ", ".join(f"{t} +{n}" for t, n in grown.most_common(12)))
    for key in ("rss", "managers", "cudd_mb", "ec1", "ec2", "history", "events", "malloc"):
        lines.append(f"{key}: {census_start[key]} -> {census_end[key]}")
    return "\n".join(lines)


def flood(seconds: float, rate: float, config: str, n_inputs: int = 9, trace: bool = False) -> dict:
    from ltl_stack.runtime.executor.setup import build_strategy, make_controller, merge_options
    from ltl_stack.runtime.resilience import characterize, resilient_executor
    from ltl_stack.spec import parse_structured

    if config != CONFIGS[0]:  # as at c79dacd: the threshold adjusts itself, fresh literals every time
        resilient_executor.fix_mmap_threshold = lambda: False
        characterize.Characterizer._shared = lambda self, values, primed: characterize._literals(
            values, self.original.inputs, primed)
    if config == CONFIGS[2]:
        characterize.HISTORY_KEPT = None  # deque(maxlen=None): every attempt kept, as before memory was bounded
    inputs = [f"i{k}" for k in range(n_inputs)]
    spec = parse_structured(spec_text(inputs), "flood.structuredslugs")
    options = merge_options({"characterize": True, "settle_steps": 0})
    strategy = build_strategy(spec, options, log=lambda _t: None)
    controller = make_controller(strategy, options, {})
    strategy.on_installed = lambda state: controller.restart_from(state)
    rng = random.Random(23)
    controller.report_many({n: False for n in inputs})
    if trace:
        import tracemalloc
        tracemalloc.start(4)
        census_start, snap_start = census(strategy), tracemalloc.take_snapshot()
    start_rss = peak = rss_mb()
    latencies = []
    period = 1.0 / rate
    begin = time.monotonic()
    next_tick, next_sample, next_mark = begin, begin, begin
    timeline = []  # (seconds, RSS MB, resyntheses) six times: flat or growing
    while time.monotonic() - begin < seconds:
        valuation = {n: rng.random() < 0.5 for n in inputs}
        t0 = time.perf_counter()
        controller.report_many(valuation)
        latencies.append(time.perf_counter() - t0)
        now = time.monotonic()
        if now >= next_sample:
            peak = max(peak, rss_mb())
            next_sample = now + 0.1
            if now >= next_mark:
                timeline.append((round(now - begin), round(rss_mb(), 1), strategy.counters.resyntheses))
                next_mark = now + seconds / 6
        next_tick += period
        time.sleep(max(0.0, next_tick - time.monotonic()))
    peak = max(peak, rss_mb())
    if trace:
        while strategy.job is not None:  # the last resynthesis finishes
            time.sleep(0.1)
        print(traced(census_start, census(strategy), snap_start, tracemalloc.take_snapshot()), file=sys.stderr)
    latencies.sort()
    return {"steps": len(latencies), "resyntheses": strategy.counters.resyntheses,
            "history": len(strategy.characterizer.history), "start_mb": round(start_rss, 1),
            "peak_mb": round(peak, 1), "growth_mb": round(peak - start_rss, 1),
            "p50_ms": round(statistics.median(latencies) * 1000, 2),
            "p99_ms": round(latencies[int(0.99 * (len(latencies) - 1))] * 1000, 2),
            "max_ms": round(latencies[-1] * 1000, 2), "timeline": timeline}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--rate", type=float, default=200.0)
    parser.add_argument("--trace", action="store_true", help="only the bounded flood, with tracemalloc and "
                        "object counts: print what grew (slower: not for the latency figures)")
    parser.add_argument("--inputs", type=int, default=9, help="input propositions (at most 2^(N-1) violating "
                        "valuations to learn; 6: about 28 resyntheses)")
    parser.add_argument("--one", choices=CONFIGS, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one or args.trace:
        print(json.dumps(flood(args.seconds, args.rate, args.one or CONFIGS[0], args.inputs, args.trace)),
              flush=True)
        return 0
    rows = {}
    for config in CONFIGS:
        done = subprocess.run([sys.executable, __file__, "--one", config, "--seconds", str(args.seconds),
                               "--rate", str(args.rate), "--inputs", str(args.inputs)],
                              capture_output=True, text=True, check=True)
        rows[config] = json.loads(done.stdout.strip().splitlines()[-1])
    print("| flood as | steps | resyntheses | kept | RSS start MB | peak MB | growth MB | step p50 ms | p99 ms | max ms |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for config, r in rows.items():
        print(f"| {config} | {r['steps']} | {r['resyntheses']} | {r['history']} | {r['start_mb']} | {r['peak_mb']} | "
              f"{r['growth_mb']} | {r['p50_ms']} | {r['p99_ms']} | {r['max_ms']} |")
    for config, r in rows.items():
        print(f"{config}: (s, RSS MB, resyntheses) " + " ".join(str(tuple(t)) for t in r["timeline"]))
    print(f"load average {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

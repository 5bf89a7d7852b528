"""Resilient execution under a violation flood (issue 23 item 7, on demand): memory and step latency.

    python test/benchmarks/bench_flood.py [--seconds 60] [--rate 200]

In process, as the executor node runs it (``build_strategy`` + ``make_controller`` with
``--characterize``: recovery moves meanwhile, each resynthesis in a worker thread, the new strategy
installed under the controller's lock with ``restart_from``): a spec of 9 inputs whose environment
promises ``!i0'``, driven at ``--rate`` Hz for ``--seconds`` by random input valuations, half of them
violating it. Every new violating valuation is learned (EC1) and resynthesized, so hundreds of
resyntheses happen. Measured per configuration, each in a fresh process: RSS at the start (after the
first strategy) and its peak (``/proc/self/statm`` every 0.1 s), the latency of every input step
(``Controller.report_many``, lock wait included), the resyntheses. The peer, in the same run: the same
flood with ``Characterizer.history`` unbounded (the old behaviour). Goal: peak RSS growth < 20 MB,
step latency p99 < 100 ms.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
INPUTS = [f"i{k}" for k in range(9)]
SPEC = ("[INPUT]\n" + "\n".join(INPUTS) + "\n\n[OUTPUT]\nstop\ngo\n\n[ENV_INIT]\n!i0\n\n[SYS_INIT]\n!go\n\n"
        "[ENV_TRANS]\n!i0'\n\n[SYS_TRANS]\ni1' -> stop'\ngo' -> !stop'\n\n[SYS_LIVENESS]\ngo | i1\n")


def rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def flood(seconds: float, rate: float, unbounded: bool) -> dict:
    from ltl_stack.runtime import characterize
    from ltl_stack.runtime.executor_setup import build_strategy, make_controller, merge_options
    from ltl_stack.spec import parse_structured

    if unbounded:
        characterize.HISTORY_KEPT = None  # deque(maxlen=None): every attempt kept, as before issue 23
    spec = parse_structured(SPEC, "flood.structuredslugs")
    options = merge_options({"characterize": True, "settle_steps": 0})
    strategy = build_strategy(spec, options, log=lambda _t: None)
    controller = make_controller(strategy, options, {})
    strategy.on_installed = lambda state: controller.restart_from(state)
    rng = random.Random(23)
    controller.report_many({n: False for n in INPUTS})
    start_rss = peak = rss_mb()
    latencies = []
    period = 1.0 / rate
    begin = time.monotonic()
    next_tick, next_sample, next_mark = begin, begin, begin
    timeline = []  # (seconds, RSS MB, resyntheses) six times: flat or growing
    while time.monotonic() - begin < seconds:
        valuation = {n: rng.random() < 0.5 for n in INPUTS}
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
    parser.add_argument("--one", choices=["bounded", "unbounded"], help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one:
        print(json.dumps(flood(args.seconds, args.rate, args.one == "unbounded")), flush=True)
        return 0
    rows = {}
    for config in ("bounded", "unbounded"):
        done = subprocess.run([sys.executable, __file__, "--one", config, "--seconds", str(args.seconds),
                               "--rate", str(args.rate)], capture_output=True, text=True, check=True)
        rows[config] = json.loads(done.stdout.strip().splitlines()[-1])
    print("| history | steps | resyntheses | kept | RSS start MB | peak MB | growth MB | step p50 ms | p99 ms | max ms |")
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

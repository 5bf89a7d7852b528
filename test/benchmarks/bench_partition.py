"""Partitioned transition relations and reused orders vs the code before them (run on demand).

    python test/benchmarks/bench_partition.py --before /path/to/old/src            # the families
    python test/benchmarks/bench_partition.py --before OLD --repeat 3 --specs basicEvasion factory_assembly_7x5_2_0errors

Each measurement is a fresh process (``--worker``) that loads the spec and answers realizability
(``ltl_stack.synthesis.is_realizable``, slugs' init semantics) and reports its own CPU time (build +
solve, ``time.process_time``: the machine is shared, wall time would measure the other users). "before"
runs with ``PYTHONPATH`` set to ``--before`` (a checkout of the old ``src``), "after" with this
checkout; the two alternate within each repeat, so drift in the machine's load hits both alike.
Both run with the order cache off (``LTL_STACK_ORDER_CACHE=off``): the columns measure the engine.
The "again" column (``--again``) is a second run of "after" with a cache folder that the run before it filled:
what a second synthesis of the same spec costs (the order reused, no sifting). Medians of
``--repeat`` runs; ``--long-repeat`` for the specs listed in ``LONG`` (30-60 s each before).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
SPECS = REPO.parent / "shared" / "specs" / "benchmarks"

FAMILIES = [
    "generated/moving_obstacle_24x24_8glitches", "generated/moving_obstacle_32x32_12glitches",
    "generated/cinderella_stepmother_n6c1_15_by_5", "generated/cinderella_stepmother_n5c3_12_by_9",
    "generated/factory_assembly_5x5_2_0errors", "generated/factory_assembly_7x5_2_0errors",
    "generated/factory_assembly_5x6_2_0errors", "generated/factory_assembly_5x5_2_10errors",
    "generated/factory_assembly_5x5_2_11errors", "slugsin/basicEvasion",
]
#: over 30 s CPU each before: measured ``--long-repeat`` times
LONG = {"generated/factory_assembly_5x6_2_0errors", "generated/factory_assembly_5x5_2_10errors",
        "generated/factory_assembly_5x5_2_11errors", "slugsin/basicEvasion"}


def worker(path: str) -> None:
    start = time.process_time()
    from ltl_stack.spec import load_spec
    from ltl_stack.synthesis import is_realizable

    spec = load_spec(path)
    loaded = time.process_time()
    realizable = is_realizable(spec, robotics_semantics=False)
    print(json.dumps({"cpu": time.process_time() - loaded, "load": loaded - start, "realizable": realizable}))


def run(src: Path, path: str, cache: str, limit: float) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src), LTL_STACK_ORDER_CACHE=cache)
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", path]
    try:
        out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True,
                             preexec_fn=lambda: _cpu_limit(limit))
        return json.loads(out.stdout.strip().splitlines()[-1])
    except (subprocess.CalledProcessError, ValueError, IndexError):
        return {"cpu": None, "realizable": None}


def _cpu_limit(seconds: float) -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_CPU, (int(seconds), int(seconds) + 5))


def fmt(values: list) -> str:
    done = [v for v in values if v is not None]
    if not done:
        return "> limit"
    return f"{statistics.median(done):.2f}" + ("" if len(done) == len(values) else f" ({len(done)}/{len(values)})")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--worker", help=argparse.SUPPRESS)
    p.add_argument("--before", required=False, help="the old code's src folder (PYTHONPATH of 'before')")
    p.add_argument("--after", type=Path, default=REPO / "src", help="the new code's src folder (default: this checkout's)")
    p.add_argument("--specs", nargs="+", default=FAMILIES, help="paths under ../shared/specs/benchmarks, no suffix")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--long-repeat", type=int, default=3)
    p.add_argument("--root", type=Path, default=SPECS, help=f"the benchmark specs (default {SPECS})")
    p.add_argument("--again", action="store_true", help="also the second run with the order reused")
    p.add_argument("--limit", type=float, default=200.0, help="CPU seconds per run")
    args = p.parse_args()
    if args.worker:
        worker(args.worker)
        return
    if not args.before:
        p.error("--before is required")
    after_src = args.after
    print(f"load at start: {os.getloadavg()[0]:.1f}", flush=True)
    print("| spec | verdict | before CPU s | after CPU s | after/before | again (order reused) s |")
    print("|---|---|---|---|---|---|")
    for name in args.specs:
        path = str(args.root / f"{name}.slugsin")
        before, after, again, verdicts = [], [], [], set()
        for _ in range(args.long_repeat if name in LONG else args.repeat):
            b = run(Path(args.before), path, "off", args.limit)
            with tempfile.TemporaryDirectory() as cache:
                a = run(after_src, path, cache, args.limit)
                r = run(after_src, path, cache, args.limit) if args.again else {"cpu": None, "realizable": None}
            before.append(b["cpu"])
            after.append(a["cpu"])
            again.append(r["cpu"])
            verdicts |= {b["realizable"], a["realizable"], r["realizable"]} - {None}
        verdict = "DISAGREE" if len(verdicts) > 1 else ("yes" if verdicts == {True} else "no" if verdicts else "?")
        done_b = [v for v in before if v is not None]
        done_a = [v for v in after if v is not None]
        ratio = f"{statistics.median(done_a) / statistics.median(done_b):.2f}" if done_a and done_b else "-"
        shown = fmt(again) if args.again else "-"
        print(f"| {Path(name).name} | {verdict} | {fmt(before)} | {fmt(after)} | {ratio} | {shown} |", flush=True)
    print(f"load at end: {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()

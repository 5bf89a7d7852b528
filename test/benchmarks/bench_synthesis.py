"""Synthesis benchmark (run on demand): ltl_stack.synthesis vs slugs' reference figures and omega.

    python test/benchmarks/bench_synthesis.py                 # everything, writes docs/benchmarks/synthesis.md
    python test/benchmarks/bench_synthesis.py --quick         # thesis specs and small family members only
    python test/benchmarks/bench_synthesis.py --grid 16:4:3   # grid patrol vs omega, alternating runs
    python test/benchmarks/bench_synthesis.py --scale 1000 4000   # 2 x N propositions in 4 clauses

Every measurement runs in a fresh subprocess (``--worker``) with a time limit, so a slow case cannot
stall the run and memory does not accumulate. Times are in-process wall times (``perf_counter``),
medians of ``--repeat`` runs (one run for cases over 5 s). slugs' figures come from
``../shared/specs/benchmarks/README.md`` and ``generated/slugs_times.csv`` (whole-process wall time on
a machine of our kind); omega (``omega.games.gr1``) runs in the same session on the same game.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
SHARED = REPO.parent / "shared" / "specs"
OUT = REPO / "docs" / "benchmarks" / "synthesis.md"

# slugs, whole process, from ../shared/specs/benchmarks/README.md: (realizability s, explicit s, states)
SLUGS_README = {
    "move_group_and_move_base": (0.048, 0.171, 472),
    "firefighting": (0.047, 0.099, 1142),
    "spheros": (0.026, 115.0, 65536),
    "two_customer_waiter_txt": (0.112, 10.1, 6824),
    "fastslow__fastslow_ICRA": (0.123, 0.688, 552),
    "basicEvasion": (267.0, None, None),
}
SLUGS_OTHERS = (0.026, 0.050)  # "most others: 26-50 ms"

GRID_MEMBERS = [(8, 2, 1), (8, 4, 2), (16, 4, 2), (16, 4, 3), (32, 4, 3)]
TECHNIQUE_SPECS = ["moving_obstacle_16x16_3glitches", "factory_assembly_5x3_1_4errors",
                   "cinderella_stepmother_n6c2_14_by_6", "two_customer_waiter_txt", "grid:16:4:2"]
EARLY_EXIT_SPECS = ["moving_obstacle_16x16_4glitches", "factory_assembly_5x4_1_0errors",
                    "cinderella_stepmother_n6c2_13_by_6"]


# --- worker --------------------------------------------------------------------------------
def load_case(case: str):
    sys.path.insert(0, str(HERE))
    if case.startswith("grid:"):
        from bench_synthesis_family import grid_patrol

        n, k, m = (int(v) for v in case.split(":")[1:])
        return grid_patrol(n, k, m), 0.0
    from ltl_stack.spec import load_spec

    start = time.perf_counter()
    spec = load_spec(case)
    return spec, time.perf_counter() - start


def scaled_spec_text(n: int) -> str:
    """2 x n propositions in 4 clauses: inputs stay on once on, outputs toggle, all outputs start
    false, one system goal (realizable; each clause is one n-ary conjunction over all propositions)."""
    def conj(parts: list[str]) -> str:
        return " ".join(["&"] * (len(parts) - 1) + parts)

    xs, ys = [f"x{i}" for i in range(n)], [f"y{i}" for i in range(n)]
    return "\n".join(["[INPUT]", *xs, "[OUTPUT]", *ys,
                      "[ENV_TRANS]", conj([f"| ! {x} {x}'" for x in xs]),
                      "[SYS_INIT]", conj([f"! {y}" for y in ys]),
                      "[SYS_TRANS]", conj([f"^ {y}' {y}" for y in ys]),
                      "[SYS_LIVENESS]", "y0", ""])


def worker(job: dict) -> dict:
    from ltl_stack.synthesis import Game, Options, SymbolicStrategy
    from ltl_stack.synthesis.fixpoint import solve

    if job["task"] == "scale":
        from ltl_stack.spec import parse_slugsin
        from ltl_stack.synthesis import synthesize

        text = scaled_spec_text(job["n"])
        start = time.perf_counter()
        spec = parse_slugsin(text)
        parsed = time.perf_counter()
        quick = synthesize(spec, strategy=False)
        checked = time.perf_counter()
        full = synthesize(spec)
        return {"realizable": quick.realizable and full.realizable, "parse": parsed - start,
                "seconds": checked - parsed, "full": time.perf_counter() - checked, "bytes": len(text)}
    spec, parse = load_case(job["case"])
    task = job["task"]
    robotics = job.get("robotics", False)
    if task == "omega":
        from bench_synthesis_family import run_omega

        realizable, seconds = run_omega(spec, robotics_semantics=robotics)
        return {"realizable": realizable, "seconds": seconds}
    opts = Options(**job.get("options", {}))
    cpu_start = time.process_time()
    start = time.perf_counter()
    game = Game(spec, interleave=job.get("interleave"), fused=job.get("fused", True))
    early = task == "realizability"
    sol = solve(game, robotics_semantics=robotics, early_exit=early, options=opts)
    solved = time.perf_counter()
    out = {"realizable": sol.realizable, "parse": parse, "seconds": solved - start, "interleaved": game.interleave,
           "game_nodes": game.nodes, "cpu": time.process_time() - cpu_start,
           "z": sol.z_iterations, "complete": sol.complete}
    if task == "explicit" and sol.realizable:
        from ltl_stack.synthesis.explicit import TooManyStates

        strategy = SymbolicStrategy(game, sol)
        try:
            automaton = strategy.explicit(max_states=job.get("max_states"))
        except TooManyStates:
            out["states"] = f"> {job['max_states']:,}"
            return out
        out["explicit"] = time.perf_counter() - solved
        out["states"] = len(automaton)
        out["end_to_end"] = parse + time.perf_counter() - start
    return out


# --- parent --------------------------------------------------------------------------------
def run(job: dict, timeout: float) -> dict:
    cmd = [sys.executable, __file__, "--worker", json.dumps(job)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"timeout": timeout}
    if proc.returncode != 0:
        return {"error": (proc.stderr.strip().splitlines() or ["?"])[-1]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def measure(job: dict, timeout: float, repeat: int, key: str = "seconds") -> dict:
    first = run(job, timeout)
    if "timeout" in first or "error" in first or first.get(key, 0) > 5 or repeat <= 1:
        return first
    results = [first] + [run(job, timeout) for _ in range(repeat - 1)]
    ok = [r for r in results if key in r]
    out = dict(ok[len(ok) // 2]) if ok else dict(first)
    for k in ("seconds", "explicit", "end_to_end", "parse", "full"):
        values = [r[k] for r in ok if k in r]
        if values:
            out[k] = statistics.median(values)
    return out


def whole_process(text: str, repeat: int, timeout: float) -> str:
    """``python -m ltl_stack.synthesis.cli FILE`` (realizability, as a user runs it): median wall
    and CPU (user + sys of the child) of ``repeat`` fresh processes."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "scaled.slugsin"
        path.write_text(text)
        walls, cpus = [], []
        for _ in range(repeat):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            start = time.perf_counter()
            try:
                proc = subprocess.run([sys.executable, "-m", "ltl_stack.synthesis.cli", str(path)],
                                      capture_output=True, text=True, timeout=timeout, check=False)
            except subprocess.TimeoutExpired:
                return f"> {timeout:.0f} s"
            walls.append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
            if proc.returncode != 0:
                return f"exit {proc.returncode}"
    return f"{fmt(statistics.median(walls))} ({fmt(statistics.median(cpus))})"


def run_slugs(slugs: str, spec: str, timeout: float) -> dict:
    """``slugs SPEC`` (realizability, default semantics) as a whole process: wall and CPU."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    try:
        proc = subprocess.run([slugs, spec], capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"timeout": timeout}
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    text = proc.stdout + proc.stderr
    realizable = "RESULT: Specification is realizable" in text
    if not realizable and "RESULT: Specification is unrealizable" not in text:
        return {"error": text.strip()[-80:] or f"exit {proc.returncode}"}
    return {"realizable": realizable, "seconds": wall,
            "cpu": after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime}


def reorder_table(args) -> int:
    """Same-run comparison of the reordering policies (and slugs) on the named specs."""
    slugs = args.slugs if args.slugs and Path(args.slugs).exists() else None
    variants = [("adaptive", {}), ("previous", {"options": {"big_game": 10**12}}),
                ("no reordering in the fixpoint", {"options": {"reorder": False}})]
    print("In-process CPU seconds of game construction + fixpoint (medians); slugs as a whole process.\n")
    print("| spec | game nodes | realizable | " + " | ".join(v for v, _ in variants)
          + " | slugs (whole process: wall / CPU) | adaptive / previous | adaptive (in process) / slugs CPU |")
    print("|---|---|---|" + "---|" * (len(variants) + 3))
    for name in args.reorder:
        case = case_path(name)
        results: dict[str, list] = {v: [] for v, _ in variants}
        theirs: list = []
        for _ in range(args.repeat):  # alternate, so drift hits every column alike
            for label, extra in variants:
                results[label].append(run({"case": case, "task": "realizability", **extra}, args.timeout))
            if slugs and (not theirs or "timeout" not in theirs[-1]):
                theirs.append(run_slugs(slugs, case, args.timeout))
        cells, med = [], {}
        for label, _ in variants:
            ok = [r["cpu"] for r in results[label] if "cpu" in r]
            med[label] = statistics.median(ok) if ok else None
            cells.append(fmt(med[label]) if ok else show(results[label][-1]))
        verdicts = {r["realizable"] for rs in results.values() for r in rs if "realizable" in r}
        verdicts |= {r["realizable"] for r in theirs if "realizable" in r}
        nodes = next((r.get("game_nodes") for r in results["adaptive"] if "game_nodes" in r), "?")
        done = [r for r in theirs if "cpu" in r]
        slugs_txt = (f"{fmt(statistics.median(r['seconds'] for r in done))} / "
                     f"{fmt(statistics.median(r['cpu'] for r in done))}" if done
                     else show(theirs[-1]) if theirs else "–")
        ratio = (f"{med['adaptive'] / med['previous']:.2f}" if med["adaptive"] and med["previous"] else "–")
        vs = (f"{med['adaptive'] / statistics.median(r['cpu'] for r in done):.2f}"
              if done and med["adaptive"] else "–")
        verdict = next(iter(verdicts)) if len(verdicts) == 1 else f"DIFFERENT {verdicts}"
        print(f"| `{name}` | {nodes} | {verdict} | {' | '.join(cells)} | {slugs_txt} | {ratio} | {vs} |", flush=True)
    print(f"\nload average {' / '.join(f'{v:.1f}' for v in os.getloadavg())} (1 / 5 / 15 min) at the end")
    return 0


def fmt(seconds) -> str:
    if seconds is None:
        return "–"
    if seconds < 1:
        return f"{seconds * 1000:.0f} ms"
    return f"{seconds:.2f} s"


def show(result: dict, key: str = "seconds") -> str:
    if "timeout" in result:
        return f"> {result['timeout']:.0f} s"
    if "error" in result:
        return f"error: {result['error'][:60]}"
    return fmt(result.get(key))


def shared_specs() -> list[Path]:
    found = sorted(SHARED.glob("*/*.slugsin"))
    found += sorted((SHARED / "benchmarks" / "slugsin").glob("*.slugsin"))
    return found


def spec_name(path: Path) -> str:
    """The spec's file stem; slugs' examples that share a stem with a thesis folder get a prefix
    (``benchmarks/slugsin/firefighting`` is slugs' example, not the thesis' firefighting spec)."""
    if path.parent.name == "slugsin" and (SHARED / path.stem).is_dir():
        return f"slugs-example/{path.stem}"
    return path.stem


def generated_specs() -> list[Path]:
    return sorted((SHARED / "benchmarks" / "generated").glob("*.slugsin"))


def slugs_generated() -> dict[str, dict]:
    path = SHARED / "benchmarks" / "generated" / "slugs_times.csv"
    if not path.exists():
        return {}
    with open(path) as f:
        return {row["spec"]: row for row in csv.DictReader(f)}


def case_path(name: str) -> str:
    if name.startswith("grid:"):
        return name
    for path in shared_specs() + generated_specs():
        if spec_name(path) == name:
            return str(path)
    raise SystemExit(f"no spec named {name}")


def main(argv: list[str] | None = None) -> int:
    # every run measures a cold start: a variable order saved by the run before (order_cache) would
    # make the second repeat of a spec cheaper than the first
    os.environ.setdefault("LTL_STACK_ORDER_CACHE", "off")
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--worker", help=argparse.SUPPRESS)
    p.add_argument("--quick", action="store_true", help="thesis specs and small family members only")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--timeout", type=float, default=120.0, help="per measurement (s)")
    p.add_argument("--out", default=str(OUT))
    p.add_argument("--json", help="also write the raw results as JSON")
    p.add_argument("--order", nargs="+", metavar="SPEC",
                   help="only compare the automatic variable order with the forced interleaved one "
                        "(realizability, early exit; spec names or grid:n:k:m) and print a table")
    p.add_argument("--grid", nargs="+", metavar="N:K:M",
                   help="only the grid patrol family vs omega for these members (e.g. 16:4:3), "
                        "ours and omega alternating, and print a table")
    p.add_argument("--reorder", nargs="+", metavar="SPEC",
                   help="only the dynamic-reordering policy: realizability (early exit, default semantics) "
                        "with the adaptive policy, with the previous one (reordering from 2,000 nodes whatever "
                        "the game's size) and without reordering in the fixpoint, beside slugs (--slugs) "
                        "in the same run, alternating; spec names (see --order) and print a table")
    p.add_argument("--slugs", help="slugs binary for --reorder (its column is skipped when absent)")
    p.add_argument("--scale", nargs="+", type=int, metavar="N",
                   help="only the 2 x N propositions / 4 clauses spec (parse, realizability, full synthesis "
                        "with strategy; fresh process each) and print a table")
    args = p.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(json.loads(args.worker))))
        return 0
    if args.scale:
        print("| propositions | spec size | realizable | parse | realizability | synthesis with strategy | "
              "`synthesize FILE` whole process, wall (CPU) |")
        print("|---|---|---|---|---|---|---|")
        for n in args.scale:
            r = measure({"case": "", "task": "scale", "n": n}, args.timeout, args.repeat)
            whole = whole_process(scaled_spec_text(n), args.repeat, args.timeout)
            print(f"| 2 × {n:,} | {r.get('bytes', 0) / 1024:.0f} KiB | {r.get('realizable', '?')} | "
                  f"{show(r, 'parse')} | {show(r)} | {show(r, 'full')} | {whole} |", flush=True)
        print(f"\nload average {' / '.join(f'{v:.1f}' for v in os.getloadavg())} (1 / 5 / 15 min) at the end")
        return 0
    if args.reorder:
        return reorder_table(args)
    if args.order:
        print("| spec | realizable | order chosen | auto | interleaved | auto / interleaved |")
        print("|---|---|---|---|---|---|")
        for name in args.order:
            job = {"case": case_path(name), "task": "realizability"}
            auto = measure(job, args.timeout, args.repeat)
            inter = measure(dict(job, interleave=True), args.timeout, args.repeat)
            ratio = f"{auto['seconds'] / inter['seconds']:.2f}" if "seconds" in auto and "seconds" in inter else "–"
            chosen = {True: "interleaved", False: "block"}.get(auto.get("interleaved"), "?")
            print(f"| `{name}` | {auto.get('realizable', '?')} | {chosen} | {show(auto)} | {show(inter)} | {ratio} |",
                  flush=True)
        return 0
    if args.grid:
        print("| member | ours (each run) | omega (each run) | omega / ours (medians) |")
        print("|---|---|---|---|")
        for member in args.grid:
            job = {"case": f"grid:{member}"}
            ours, omega = [], []
            for _ in range(args.repeat):  # alternate, so drift hits both sides alike
                ours.append(run(dict(job, task="synthesis"), max(args.timeout, 300.0)))
                omega.append(run(dict(job, task="omega"), max(args.timeout, 300.0)))
            a = [r["seconds"] for r in ours if "seconds" in r]
            b = [r["seconds"] for r in omega if "seconds" in r]
            ratio = f"{statistics.median(b) / statistics.median(a):.1f}" if a and b else "–"
            print(f"| {member} | {', '.join(show(r) for r in ours)} | {', '.join(show(r) for r in omega)} "
                  f"| {ratio} |", flush=True)
        return 0
    if not SHARED.is_dir():
        print(f"bench_synthesis: {SHARED} is absent; nothing to measure", file=sys.stderr)
        return 2
    started = time.time()
    raw: dict = {"shared": {}, "generated": {}, "techniques": {}, "early_exit": {}, "grid": {}}
    lines = ["# Synthesis benchmark", "",
             f"Command: `python test/benchmarks/bench_synthesis.py{' --quick' if args.quick else ''}` "
             f"(repeat {args.repeat}, limit {args.timeout:.0f} s per measurement), "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(started))}, {platform.machine()}, "
             f"{os.cpu_count()} cores shared with other developers' jobs: figures were taken under load "
             "and drift up to 2x; compare ratios within this run.", "",
             "Our times are in-process wall times (median); slugs' are whole-process times from "
             "`../shared/specs/benchmarks/` (a slugs process costs ~27 ms even on a trivial spec).", ""]

    def log(msg: str) -> None:
        print(f"[{time.time() - started:6.0f} s] {msg}", file=sys.stderr, flush=True)

    # 1. shared specs
    lines += ["## Shared specs (slugs' default init semantics)", "",
              "| spec | realizable | parse | realizability (early exit) | synthesis (full fixpoint) | "
              "explicit | states | slugs realizability | slugs explicit (states) | ours / slugs |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for path in shared_specs():
        name = spec_name(path)
        real = measure({"case": str(path), "task": "realizability"}, args.timeout, args.repeat)
        full = measure({"case": str(path), "task": "explicit", "max_states": 200_000},
                       min(args.timeout, 60.0) if name == "spheros" else args.timeout, args.repeat)
        if "timeout" in full or (full.get("realizable") and "explicit" not in full):
            # too big to enumerate: measure the fixpoint alone
            states = full.get("states", "–") if "timeout" not in full else "not in time"
            full = measure({"case": str(path), "task": "synthesis"}, args.timeout, args.repeat)
            full["states"] = states
        raw["shared"][name] = {"realizability": real, "explicit": full}
        slugs = SLUGS_README.get(name)
        slugs_real = slugs[0] if slugs else None
        slugs_expl = f"{fmt(slugs[1])} ({slugs[2]})" if slugs and slugs[1] else "–"
        ours = real.get("parse", 0) + real.get("seconds", 0) if "seconds" in real else None
        ratio = f"{ours / slugs_real:.2f}" if ours and slugs_real else (
            f"{ours / SLUGS_OTHERS[1]:.2f} (vs 50 ms)" if ours else "–")
        lines.append(f"| `{name}` | {real.get('realizable', '?')} | {show(real, 'parse')} | {show(real)} | "
                     f"{show(full)} | {show(full, 'explicit') if 'explicit' in full else '–'} | "
                     f"{full.get('states', '–')} | {fmt(slugs_real) if slugs_real else '26–50 ms'} | "
                     f"{slugs_expl} | {ratio} |")
        log(f"{name}: {real} {full}")
    ex8 = raw["shared"].get("move_group_and_move_base", {}).get("explicit", {})
    if "end_to_end" in ex8:
        lines += ["", f"Thesis Ex. 8 end to end (parse, realizability, explicit strategy, in process): "
                      f"**{fmt(ex8['end_to_end'])}** (goal < 0.5 s; slugs: 48 ms + 171 ms as two processes)."]

    # 2. generated families
    if not args.quick:
        table = slugs_generated()
        lines += ["", "## slugs' generated families (realizability, default semantics)", "",
                  "| spec | inputs+outputs | realizable | ours (early exit) | ours (full) | slugs | ours / slugs | "
                  "ours explicit (states) | slugs explicit, 30 s limit (states) |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for path in generated_specs():
            name = path.stem
            row = table.get(name, {})
            real = measure({"case": str(path), "task": "realizability"}, min(args.timeout, 60.0), args.repeat)
            full = measure({"case": str(path), "task": "synthesis"}, min(args.timeout, 60.0), 1) \
                if real.get("realizable") is False else {"note": "same"}
            expl = measure({"case": str(path), "task": "explicit", "max_states": 200_000},
                           min(args.timeout, 60.0), 1) if real.get("realizable") else {}
            raw["generated"][name] = {"realizability": real, "full": full, "explicit": expl}
            if "explicit" in expl:
                expl_txt = f"{fmt(expl['explicit'])} ({expl['states']})"
            elif "timeout" in expl or "error" in expl:
                expl_txt = show(expl)
            else:
                expl_txt = f"– ({expl['states']} states)" if "states" in expl else "–"
            slugs_expl = {"yes": f"{float(row.get('expl_wall_median_s') or 0):.2f} s ({row.get('expl_states')})",
                          "timeout": "> 30 s"}.get(row.get("expl_result", ""), "–")
            slugs_s = row.get("real_wall_median_s") or None
            slugs_txt = f"{float(slugs_s):.2f} s" if slugs_s else (
                "> 60 s" if row.get("probe_result_60s") == "timeout" else "–")
            ours = real.get("parse", 0) + real["seconds"] if "seconds" in real else None
            ratio = f"{ours / float(slugs_s):.2f}" if ours and slugs_s else (
                "< 1 (slugs timed out)" if ours and row.get("probe_result_60s") == "timeout" else "–")
            size = f"{row.get('n_in_bool', '?')}+{row.get('n_out_bool', '?')}"
            lines.append(f"| `{name}` | {size} | {real.get('realizable', '?')} | {show(real)} | "
                         f"{show(full) if 'note' not in full else '(same run)'} | {slugs_txt} | {ratio} | "
                         f"{expl_txt} | {slugs_expl} |")
            log(f"{name}: {real}")

    # 3. techniques
    lines += ["", "## Techniques (each switched off alone; full fixpoint, default semantics)", "",
              "| case | all on | no recycling | no reordering | not interleaved | unfused cpre | "
              "transition-based iterates | no Gauss-Seidel in Y rounds |",
              "|---|---|---|---|---|---|---|---|"]
    variants = [("all on", {}), ("no recycling", {"options": {"recycle": False}}),
                ("no reordering", {"options": {"reorder": False}}), ("not interleaved", {"interleave": False}),
                ("unfused", {"fused": False}), ("transition-based", {"options": {"state_based": False}}),
                ("no Gauss-Seidel", {"options": {"gauss_seidel": False}})]
    for name in TECHNIQUE_SPECS if not args.quick else ["grid:8:4:2", "move_group_and_move_base"]:
        try:
            case = case_path(name)
        except SystemExit:
            continue
        cells = []
        base = None
        for label, extra in variants:
            r = measure({"case": case, "task": "synthesis", **extra}, args.timeout, args.repeat)
            raw["techniques"].setdefault(name, {})[label] = r
            if label == "all on":
                base = r.get("seconds")
                cells.append(show(r))
            else:
                factor = f" (×{r['seconds'] / base:.1f})" if base and "seconds" in r else ""
                cells.append(show(r) + factor)
            log(f"technique {name} {label}: {r}")
        lines.append(f"| `{name}` | " + " | ".join(cells) + " |")
    lines += ["", "(×k = time with the technique off / time with everything on. State-based iterates apply "
                  "only when no liveness formula has primes; otherwise that column equals 'all on'.)"]
    lines += ["", "### Early exit on realizability-only queries (unrealizable specs)", "",
              "| spec | with early exit | without | Z iterations with / without |", "|---|---|---|---|"]
    for name in EARLY_EXIT_SPECS if not args.quick else []:
        try:
            case = case_path(name)
        except SystemExit:
            continue
        on = measure({"case": case, "task": "realizability"}, args.timeout, args.repeat)
        off = measure({"case": case, "task": "synthesis"}, args.timeout, args.repeat)
        raw["early_exit"][name] = {"on": on, "off": off}
        lines.append(f"| `{name}` | {show(on)} | {show(off)} | {on.get('z', '?')} / {off.get('z', '?')} |")
        log(f"early exit {name}: {on} {off}")

    # 4. grid family vs omega
    lines += ["", "## Grid patrol family vs omega (same game, same session)", "",
              "n×n grid, k goals, m moving obstacles (`bench_synthesis_family.grid_patrol`); both solvers "
              "use CUDD through `dd`; omega's time is its fixpoint and init check only (the BDDs of the spec "
              "are built for it untimed), ours is Game construction plus fixpoint.", "",
              "| member | bits in+out | realizable (ours / omega) | ours | omega | omega / ours |",
              "|---|---|---|---|---|---|"]
    members = GRID_MEMBERS if not args.quick else GRID_MEMBERS[:3]
    for n, k, m in members:
        case = f"grid:{n}:{k}:{m}"
        ours = measure({"case": case, "task": "synthesis"}, args.timeout, args.repeat)
        omega = measure({"case": case, "task": "omega"}, max(args.timeout, 300.0), args.repeat)
        raw["grid"][case] = {"ours": ours, "omega": omega}
        b = max(1, (n - 1).bit_length())
        if "seconds" in ours and "seconds" in omega:
            ratio = f"{omega['seconds'] / ours['seconds']:.1f}"
        elif "seconds" in ours and "timeout" in omega:
            ratio = f"> {omega['timeout'] / ours['seconds']:.1f}"
        else:
            ratio = "–"
        lines.append(f"| {n}×{n}, k={k}, m={m} | {m * b}+{2 * b} | {ours.get('realizable', '?')} / "
                     f"{omega.get('realizable', '?')} | {show(ours)} | {show(omega)} | {ratio} |")
        log(f"grid {case}: ours {ours} omega {omega}")
    lines += ["", f"Total benchmark time {time.time() - started:.0f} s.", ""]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    existing = out.read_text() if out.exists() else ""
    marker = "<!-- measured by bench_synthesis.py above; notes below are kept -->"
    notes = existing.split(marker, 1)[1] if marker in existing else ""
    out.write_text("\n".join(lines) + "\n" + marker + notes)
    if args.json:
        Path(args.json).write_text(json.dumps(raw, indent=1))
    print(f"wrote {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

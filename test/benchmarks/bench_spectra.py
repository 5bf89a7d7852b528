"""ltl_stack beside Spectra's C GR(1) solver on the same games, whole processes (run on demand).

    python test/benchmarks/bench_spectra.py --spectra-classes DIR --spectra-lib DIR [--repeat 3] [--specs ...]

Spectra (github.com/SpectraSynthesizer: spectra-synt's Java bundles compiled with javac, spectra-cudd's
``libcudd.so`` built with -O3; the recipe is in docs/benchmarks/spectra.md, nothing of Spectra is in
this repository) reads its games from the Spectra language; this benchmark feeds it the same
``.slugsin`` games ltl_stack reads, through our own harness ``spectra_harness/SlugsinGR1.java``: it
builds the players' variables, initial conditions, safety (as Spectra's decomposed transitions with
its quantification schedule) and justice with Spectra's ``PlayerModule`` and answers realizability
with ``GR1GameImplC`` under the IDE's default options (CUDD, dynamic reordering, "all" optimisations).

Each run is a fresh process: the JVM for Spectra (``-XX:+UseSerialGC``, so that no parallel collector
threads add CPU), ``python bench_partition.py --worker`` for ltl_stack (``is_realizable``, slugs'
init semantics, the order cache off). Reported per game, medians of ``--repeat`` runs, the two
alternating: the whole process's CPU (user + system, ``RUSAGE_CHILDREN``: start-up included) and the
build + solve CPU each process measures of itself, the ratio ltl_stack / Spectra of both, and the
verdicts (a disagreement is printed as DISAGREE).
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
SPECS = REPO.parent / "shared" / "specs" / "benchmarks"
HARNESS = HERE / "spectra_harness" / "SlugsinGR1.java"

#: cinderella (no Spectra figure in the issue) and the games whose Spectra figures the issue quotes
GAMES = [
    "generated/cinderella_stepmother_n6c1_15_by_5", "generated/cinderella_stepmother_n5c3_12_by_9",
    "generated/moving_obstacle_32x32_12glitches", "generated/factory_assembly_7x5_2_0errors",
    "generated/factory_assembly_5x6_2_0errors", "generated/factory_assembly_5x5_2_10errors",
    "generated/factory_assembly_5x5_2_11errors", "slugsin/basicEvasion",
]
#: Spectra takes 30-45 s CPU on these: measured ``--long-repeat`` times
LONG = {"generated/factory_assembly_5x6_2_0errors", "generated/factory_assembly_5x5_2_10errors",
        "generated/factory_assembly_5x5_2_11errors", "slugsin/basicEvasion"}


def compile_harness(classes: Path, out: Path) -> None:
    """Compile our harness against Spectra's compiled classes (once)."""
    target = out / "SlugsinGR1.class"
    if target.exists() and target.stat().st_mtime >= HARNESS.stat().st_mtime:
        return
    out.mkdir(parents=True, exist_ok=True)
    subprocess.run(["javac", "-nowarn", "-cp", str(classes), "-d", str(out), str(HARNESS)], check=True)


def timed(cmd: list, env: dict, limit: float) -> tuple:
    """(the process's last stdout line as JSON or None, its CPU seconds user + system)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=limit * 5,
                             preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_CPU, (int(limit), int(limit) + 5)))
        report = json.loads(out.stdout.strip().splitlines()[-1]) if out.returncode == 0 else None
    except (subprocess.TimeoutExpired, ValueError, IndexError):
        report = None
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return report, cpu


def median(values: list) -> float | None:
    done = [v for v in values if v is not None]
    return statistics.median(done) if done else None


def fmt(value: float | None) -> str:
    return "> limit" if value is None else f"{value:.2f}"


def ratio(a: float | None, b: float | None) -> str:
    return f"{a / b:.2f}" if a is not None and b else "-"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spectra-classes", type=Path, required=True, help="spectra-synt's bundles compiled (javac -d DIR)")
    p.add_argument("--spectra-lib", type=Path, required=True, help="folder holding spectra-cudd's libcudd.so")
    p.add_argument("--harness-out", type=Path, default=Path("/tmp/ltl_stack_spectra_harness"),
                   help="where the harness is compiled")
    p.add_argument("--src", type=Path, default=REPO / "src", help="ltl_stack's src folder (default: this checkout's)")
    p.add_argument("--specs", nargs="+", default=GAMES, help="paths under --root, no suffix")
    p.add_argument("--root", type=Path, default=SPECS)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--long-repeat", type=int, default=3)
    p.add_argument("--limit", type=float, default=300.0, help="CPU seconds per run")
    args = p.parse_args()
    compile_harness(args.spectra_classes, args.harness_out)
    java = ["java", "-XX:+UseSerialGC", f"-Djava.library.path={args.spectra_lib}",
            "-cp", f"{args.spectra_classes}{os.pathsep}{args.harness_out}", "SlugsinGR1"]
    ours = [sys.executable, str(HERE / "bench_partition.py"), "--worker"]
    ours_env = dict(os.environ, PYTHONPATH=str(args.src), LTL_STACK_ORDER_CACHE="off")
    print(f"load at start: {os.getloadavg()[0]:.1f}", flush=True)
    print("| game | verdict | Spectra process CPU s | ltl_stack process CPU s | ratio | "
          "Spectra build+solve s | ltl_stack build+solve s | ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for name in args.specs:
        path = str(args.root / f"{name}.slugsin")
        sp_whole, sp_in, lt_whole, lt_in, verdicts = [], [], [], [], set()
        for _ in range(args.long_repeat if name in LONG else args.repeat):
            report, cpu = timed(java + [path], dict(os.environ), args.limit)
            sp_whole.append(cpu if report else None)
            sp_in.append(report["cpu"] if report else None)
            verdicts.add(("spectra", report["realizable"]) if report else None)
            report, cpu = timed(ours + [path], ours_env, args.limit)
            lt_whole.append(cpu if report else None)
            lt_in.append(report["cpu"] if report else None)
            verdicts.add(("ltl_stack", report["realizable"]) if report else None)
        answers = {v for _, v in verdicts - {None}}
        verdict = "DISAGREE" if len(answers) > 1 else ("yes" if answers == {True} else "no" if answers else "?")
        sw, lw, si, li = median(sp_whole), median(lt_whole), median(sp_in), median(lt_in)
        print(f"| {Path(name).name} | {verdict} | {fmt(sw)} | {fmt(lw)} | {ratio(lw, sw)} | "
              f"{fmt(si)} | {fmt(li)} | {ratio(li, si)} |", flush=True)
    print(f"load at end: {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()

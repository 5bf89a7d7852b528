"""Explicit strategy export vs slugs, whole process (run on demand).

    python test/benchmarks/bench_explicit.py --slugs SLUGS [--repeat 3] [--cooperative]

SLUGS: a slugs binary built from its public sources (github.com/VerifiableRobotics/slugs: ``cd src &&
make``; CUDD comes with it, no qmake needed).

For each shared spec: ``synthesize SPEC --no-robotics-semantics --no-cooperative --slugs-json OUT``
(slugs' default init semantics, any winning move: what slugs computes) against
``slugs --explicitStrategy --jsonOutput SPEC OUT``, both as whole processes, alternating, medians of
``--repeat`` runs; states counted in the written files. Our in-process export time
(``explicit_seconds`` of ``--json``) is listed too. slugs runs with a ``--slugs-timeout`` (120 s);
without ``--slugs`` (or when the path does not exist) its columns are skipped.

Specs: the thesis' (../shared/specs), slugs' examples (benchmarks/slugsin, realizable ones), and the
generated family members for which slugs' explicit strategy finished in its reference run
(``generated/slugs_times.csv``). Goal: no slower than slugs, and no more states, wherever slugs
finishes. Writes docs/benchmarks/explicit.md.

``--cooperative``: the cooperative strategy on both sides, our default export (``synthesize SPEC
--no-robotics-semantics --slugs-json OUT``) against ``slugs --cooperativeGR1Strategy --explicitStrategy
--jsonOutput SPEC OUT``, to docs/benchmarks/explicit_cooperative.md (the default export is
no larger than slugs' in the same mode).

Bytecode (as in ``bench_cli_latency.py``): the session that runs the suite sets
``PYTHONDONTWRITEBYTECODE``, so every process of ours would compile ~30 modules from source
(~0.1-0.16 s CPU that an installed package never pays: it has its ``.pyc`` files); our processes
run with a private ``PYTHONPYCACHEPREFIX`` instead, warmed by one untimed run.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"  # the project's shared folder, beside the repository
SPECS = SHARED / "specs"
OUT = ROOT / "docs" / "benchmarks" / "explicit.md"
OUT_COOPERATIVE = ROOT / "docs" / "benchmarks" / "explicit_cooperative.md"

THESIS = ["move_group_and_move_base/move_group_and_move_base.slugsin", "firefighting/firefighting.slugsin",
          "simple/simple.slugsin"]
GENERATED = ["factory_assembly_4x3_1_1errors", "factory_assembly_5x3_1_0errors", "factory_assembly_5x3_1_4errors",
             "moving_obstacle_8x8_0glitches"]
SKIP = {"basicEvasion"}  # realizability alone takes slugs minutes


def synthesize_command() -> list[str]:
    """The installed script when it is on PATH (as a user runs it), else the module."""
    script = shutil.which("synthesize")
    return [script] if script else [sys.executable, "-m", "ltl_stack.synthesis.cli"]


def specs(selected: list[str] | None) -> list[Path]:
    if selected:
        return [Path(s) for s in selected]
    found = [SPECS / s for s in THESIS]
    found += sorted(p for p in (SPECS / "benchmarks" / "slugsin").glob("*.slugsin") if p.stem not in SKIP)
    found += [SPECS / "benchmarks" / "generated" / f"{g}.slugsin" for g in GENERATED]
    return [p for p in found if p.exists()]


def cpu_of_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


#: the environment of our processes: bytecode cached in a private folder (see the module docstring)
CHILD_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def run_ours(spec: Path, out: Path, extra: list[str]) -> dict:
    """``extra`` holds ``--cooperative`` for the cooperative comparison; else ``--no-cooperative`` is added."""
    mode = [] if "--cooperative" in extra else ["--no-cooperative"]
    cmd = [*synthesize_command(), str(spec), "--no-robotics-semantics", *mode, "--slugs-json", str(out),
           "--json", "--quiet", "--max-states", "3000000", *extra]
    start, cpu = time.perf_counter(), cpu_of_children()
    done = subprocess.run(cmd, capture_output=True, text=True, check=False, env=CHILD_ENV)
    wall, cpu = time.perf_counter() - start, cpu_of_children() - cpu
    if done.returncode not in (0, 10):
        raise RuntimeError(f"{' '.join(cmd)}: exit {done.returncode}: {done.stderr.strip()}")
    summary = json.loads(done.stdout)
    summary["wall"], summary["cpu"] = wall, cpu
    return summary


def run_slugs(slugs: str, spec: Path, out: Path, timeout: float, extra: list[str]) -> dict:
    cmd = [slugs, "--explicitStrategy", *extra, "--jsonOutput", str(spec), str(out)]
    out.unlink(missing_ok=True)
    start, cpu = time.perf_counter(), cpu_of_children()
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, check=False, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"wall": None}
    wall, cpu = time.perf_counter() - start, cpu_of_children() - cpu
    if done.returncode != 0 or not out.exists():
        return {"wall": wall, "error": done.stderr.strip()[-200:]}
    return {"wall": wall, "cpu": cpu, "states": len(json.loads(out.read_text())["nodes"])}


def measure(spec: Path, slugs: str | None, repeat: int, timeout: float, ours_extra: list[str],
            slugs_extra: list[str]) -> dict:
    """Alternating runs; slugs is not repeated once it timed out."""
    ours, theirs = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(repeat):
            ours.append(run_ours(spec, Path(tmp) / "ours.json", ours_extra))
            if not ours[-1]["realizable"]:
                return {"realizable": False}
            if slugs and (not theirs or theirs[-1]["wall"] is not None):
                theirs.append(run_slugs(slugs, spec, Path(tmp) / "slugs.json", timeout, slugs_extra))
    result = {"realizable": True, "ours_wall": statistics.median(r["wall"] for r in ours),
              "ours_cpu": statistics.median(r["cpu"] for r in ours),
              "ours_explicit": statistics.median(r["explicit_seconds"] for r in ours),
              "ours_states": ours[-1]["states"], "ours_plain": ours[-1].get("states_without_recovery")}
    if theirs:
        finished = [r for r in theirs if r["wall"] is not None and "states" in r]
        result["slugs_timeout"] = any(r["wall"] is None for r in theirs)
        result["slugs_error"] = next((r["error"] for r in theirs if "error" in r), None)
        if finished:
            result["slugs_wall"] = statistics.median(r["wall"] for r in finished)
            result["slugs_cpu"] = statistics.median(r["cpu"] for r in finished)
            result["slugs_states"] = finished[-1]["states"]
            result["slugs_runs"] = len(finished)
    return result


def fmt_s(value: float | None) -> str:
    return "–" if value is None else f"{value:.3f} s" if value < 10 else f"{value:.1f} s"


def row(name: str, r: dict, slugs: str | None, timeout: float) -> str:
    if not r["realizable"]:
        return f"| {name} | unrealizable | | | | | | |"
    ours = f"{fmt_s(r['ours_wall'])} / {fmt_s(r['ours_cpu'])} ({fmt_s(r['ours_explicit'])})"
    states = f"{r['ours_states']:,}" + (f" ({r['ours_plain']:,} without recovery)" if r.get("ours_plain") else "")
    if not slugs:
        return f"| {name} | {ours} | {states} | (no slugs) | | | | |"
    if "slugs_wall" not in r:
        what = f"> {timeout:.0f} s" if r.get("slugs_timeout") else f"failed: {r.get('slugs_error')}"
        return f"| {name} | {ours} | {states} | {what} | – | – | – | – |"
    size = r["ours_states"] / r["slugs_states"] if r["slugs_states"] else float("nan")
    return (f"| {name} | {ours} | {states} | {fmt_s(r['slugs_wall'])} / {fmt_s(r['slugs_cpu'])} "
            f"({r['slugs_runs']} runs) | {r['slugs_states']:,} | **{r['ours_wall'] / r['slugs_wall']:.2f}** | "
            f"**{r['ours_cpu'] / max(r['slugs_cpu'], 1e-3):.2f}** | {size:.2f} |")


HEADER = ["| spec | ours: wall / CPU, whole process (in-process export) | our states | slugs: wall / CPU | "
          "slugs states | wall ours / slugs | CPU ours / slugs | states ours / slugs |",
          "|---|---|---|---|---|---|---|---|"]


def main(argv: list[str] | None = None) -> int:
    # every run measures a cold start: a variable order saved by the run before (order_cache) would
    # make the second repeat of a spec cheaper than the first
    os.environ.setdefault("LTL_STACK_ORDER_CACHE", "off")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slugs", help="path of the slugs binary (its columns are skipped without it)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--slugs-timeout", type=float, default=120.0)
    parser.add_argument("--cooperative", action="store_true",
                        help="both sides cooperative: our default against slugs --cooperativeGR1Strategy")
    parser.add_argument("specs", nargs="*", help="spec files (default: the shared specs above)")
    args = parser.parse_args(argv)
    ours_extra, slugs_extra = (["--cooperative"], ["--cooperativeGR1Strategy"]) if args.cooperative else ([], [])
    slugs = args.slugs if args.slugs and Path(args.slugs).exists() else None
    if args.slugs and not slugs:
        print(f"slugs not found at {args.slugs}: its columns are skipped", file=sys.stderr)
    rows = []
    pycache = tempfile.TemporaryDirectory(prefix="bench_explicit_pycache_")
    CHILD_ENV["PYTHONPYCACHEPREFIX"] = pycache.name
    chosen = specs(args.specs)
    if chosen:
        with tempfile.TemporaryDirectory() as tmp:
            run_ours(chosen[0], Path(tmp) / "warm.json", [])  # writes the bytecode cache, untimed
    print("\n".join(HEADER), flush=True)
    for spec in chosen:
        name = spec.stem if "generated" in spec.parts or "slugsin" in spec.parts else f"{spec.parent.name} (thesis)"
        rows.append(row(name, measure(spec, slugs, args.repeat, args.slugs_timeout, ours_extra, slugs_extra), slugs,
                        args.slugs_timeout))
        print(rows[-1], flush=True)
    ours_cmd = (f"{' '.join(Path(c).name for c in synthesize_command())} SPEC --no-robotics-semantics "
                f"{'--cooperative' if args.cooperative else '--no-cooperative'} --slugs-json OUT")
    slugs_cmd = f"slugs --explicitStrategy {'--cooperativeGR1Strategy ' if args.cooperative else ''}--jsonOutput SPEC OUT"
    text = "\n".join([
        "# Explicit strategy export vs slugs" + (", both cooperative" if args.cooperative else ""),
        "",
        f"`python test/benchmarks/bench_explicit.py --slugs SLUGS --repeat {args.repeat}"
        f"{' --cooperative' if args.cooperative else ''}` on {platform.machine()}, "
        f"Python {platform.python_version()}, {time.strftime('%Y-%m-%d %H:%M')} (machine shared with other work; "
        "ours and slugs alternate, so the ratio of one row is a same-run figure; CPU is user + system time of "
        "the process, the steadier figure on a loaded machine). Our processes use a warmed bytecode cache, "
        f"as an installed package does. Load average at the end: {' / '.join(f'{v:.1f}' for v in os.getloadavg())}.",
        "",
        f"Ours: `{ours_cmd}`; slugs: `{slugs_cmd}`. Medians of the runs; "
        f"slugs' time limit {args.slugs_timeout:.0f} s.",
        "",
        *HEADER,
        *rows,
        "",
    ])
    if not args.specs:
        out = OUT_COOPERATIVE if args.cooperative else OUT
        out.write_text(text)
        print(f"written {out}")
    print(f"load average {' / '.join(f'{v:.1f}' for v in os.getloadavg())} (1 / 5 / 15 min) at the end")
    pycache.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())

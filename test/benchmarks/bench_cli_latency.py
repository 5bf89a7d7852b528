"""Whole-process latency of ``synthesize`` as a user runs it, against slugs in the same run (issue 16).

    python test/benchmarks/bench_cli_latency.py --slugs /root/.cache/slugs/src/src/slugs
    python test/benchmarks/bench_cli_latency.py --slugs PATH --generated 1.0   # + generated members up to 1 s
    python test/benchmarks/bench_cli_latency.py --pythonpath /tmp/old/src      # an older checkout's code

Each spec is run as a fresh process, alternating ours and slugs' (and rosrun's) runs so that load
drift hits every column alike; the table gives medians of ``--repeat`` runs (wall and CPU time of
the child) and the ratio ours / slugs within the run. Columns:

- ``ours``: the devel-space script on PATH (``$LTL_STACK_WS/devel/lib/ltl_stack/synthesize``, what
  ``rosrun`` executes), default options (robotics init semantics), realizability only (no export);
- ``slugs``: ``slugs --sysInitRoboticsSemantics SPEC`` (the same question); skipped without ``--slugs``;
- ``rosrun``: ``rosrun ltl_stack synthesize SPEC``, and ``rosrun --prefix true ...``, which finds the
  script the same way and then runs ``true`` instead: rosrun's own cost, which is not ours.

Bytecode: the session that runs the suite sets ``PYTHONDONTWRITEBYTECODE``; an installed package
has its ``.pyc`` files (``catkin_make install`` compiles them, a devel space writes them on the
first run), so the children run with a private ``PYTHONPYCACHEPREFIX`` warmed by one untimed run.
The verdicts of ours and slugs' are compared; a disagreement is marked ``DIFFERENT``.
"""
from __future__ import annotations

import argparse
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
SHARED = REPO.parent / "shared" / "specs"
OUT = REPO / "docs" / "benchmarks" / "cli_latency.md"
#: slugs' examples too slow for a latency table (slugs: > 400 s; ours ~20 s): bench_synthesis.py
SLOW = {"basicEvasion"}


def shared_specs() -> list[Path]:
    found = sorted(SHARED.glob("*/*.slugsin"))
    found += sorted((SHARED / "benchmarks" / "slugsin").glob("*.slugsin"))
    return [p for p in found if p.stem not in SLOW]


def generated_specs(limit: float) -> list[Path]:
    """Generated family members whose slugs realizability time (``slugs_times.csv``) is at most ``limit`` s."""
    import csv

    table = SHARED / "benchmarks" / "generated" / "slugs_times.csv"
    if limit <= 0 or not table.exists():
        return []
    with open(table) as f:
        rows = [r for r in csv.DictReader(f) if r.get("real_wall_median_s")]
    return [SHARED / "benchmarks" / "generated" / f"{r['spec']}.slugsin" for r in rows
            if float(r["real_wall_median_s"]) <= limit]


def name_of(path: Path) -> str:
    if path.parent.name == "slugsin":
        return f"slugs/{path.stem}"
    if path.parent.name == "generated":
        return f"gen/{path.stem}"
    return path.stem


def run(cmd: list[str], env: dict[str, str], timeout: float) -> dict:
    """Wall and CPU (user + sys, ``os.wait4``) seconds of one child process, its exit code and output."""
    with tempfile.TemporaryFile() as out:
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, env=env)
        killer = threading.Timer(timeout, proc.kill)
        killer.start()
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        killer.cancel()
        proc.returncode = os.waitstatus_to_exitcode(status)
        if wall >= timeout:
            return {"timeout": timeout}
        out.seek(0)
        text = out.read().decode(errors="replace")
    return {"wall": wall, "cpu": usage.ru_utime + usage.ru_stime, "code": proc.returncode, "out": text}


def verdict_ours(r: dict) -> str:
    return {0: "yes", 10: "no"}.get(r.get("code"), f"exit {r.get('code')}")


def verdict_slugs(r: dict) -> str:
    text = r.get("out", "")
    if "Specification is realizable" in text:
        return "yes"
    if "Specification is unrealizable" in text:
        return "no"
    return "?"


def med(runs: list[dict], key: str) -> float | None:
    values = [r[key] for r in runs if key in r]
    return statistics.median(values) if values else None


def ms(value: float | None) -> str:
    return "–" if value is None else f"{value * 1000:.0f}"


def executor_start(repeat: int, timeout: float, env: dict[str, str]) -> list[str]:
    """``controller_executor`` on thesis Ex. 8 (config/clean_and_patrol) through a real master: from
    starting the process to its first ``~state`` with a state (latched; received by a subscriber
    started before it), the robot assumed in topLane and every other input false (``--init-props``), so no sensor node is needed."""
    sys.path.insert(0, str(REPO / "test"))
    import rospy  # ROS only for this mode: the latency table needs no master
    from helpers import RosMaster

    from ltl_stack.msg import ControllerState
    from ltl_stack.spec import load_spec

    config = REPO / "config" / "clean_and_patrol"
    spec = config / "clean_and_patrol.structuredslugs"
    inputs = load_spec(spec).inputs
    script = Path(os.environ["LTL_STACK_WS"], "devel", "lib", "ltl_stack", "controller_executor")
    work = Path(tempfile.mkdtemp(prefix="bench-exec-start-"))
    master = RosMaster(work)
    os.environ["ROS_MASTER_URI"] = master.uri
    env = dict(env, ROS_MASTER_URI=master.uri)
    rospy.init_node("bench_executor_start", anonymous=True, disable_signals=True)
    first: list[float] = []
    def on_state(msg: ControllerState) -> None:
        if msg.state_id >= 0:
            first.append(time.perf_counter())

    # the mapping puts the node in its namespace; a plain run leaves it at the root
    subs = [rospy.Subscriber(f"{ns}/controller_executor/state", ControllerState, on_state)
            for ns in ("/clean_and_patrol", "")]
    times = []
    try:
        for k in range(repeat + 1):  # the first run only warms the bytecode cache
            first.clear()
            start = time.perf_counter()
            proc = subprocess.Popen([str(script), str(spec), str(config / "clean_and_patrol.yaml"), "--init-props",
                                     ",".join(f"{v}={int(v == 'topLane_rc')}" for v in inputs)], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            while not first and time.perf_counter() - start < timeout and proc.poll() is None:
                time.sleep(0.001)
            if first and k:
                times.append(first[0] - start)
            print(f"run {k}: {'%.0f ms' % ((first[0] - start) * 1000) if first else 'no state'}", file=sys.stderr)
            proc.send_signal(2)
            try:
                proc.wait(20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            deadline = time.perf_counter() + 30
            while any(master.publishers(f"{ns}/controller_executor/state") for ns in ("/clean_and_patrol", "")) \
                    and time.perf_counter() < deadline:
                time.sleep(0.05)
    finally:
        for sub in subs:
            sub.unregister()
        rospy.signal_shutdown("done")
        master.shutdown()
        shutil.rmtree(work, ignore_errors=True)
    line = (f"controller_executor, Ex. 8 (config/clean_and_patrol), start to first ~state through a real master: "
            f"median {statistics.median(times) * 1000:.0f} ms over {len(times)} runs "
            f"({', '.join(f'{t * 1000:.0f}' for t in times)} ms), load average {os.getloadavg()[0]:.1f}"
            if times else "controller_executor: no state received")
    return [line]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--slugs", help="the slugs binary (built from source); without it the slugs column is skipped")
    p.add_argument("--repeat", type=int, default=5, help="runs per column and spec (median; default 5)")
    p.add_argument("--rosrun", action=argparse.BooleanOptionalAction, default=True,
                   help="also run through rosrun and measure rosrun's own cost (default on)")
    p.add_argument("--generated", type=float, default=0.0, metavar="S",
                   help="also the generated family members where slugs needs at most S seconds")
    p.add_argument("--only", nargs="+", metavar="NAME", help="only the specs whose name contains one of these")
    p.add_argument("--pythonpath", help="put this source folder first on PYTHONPATH (measure another checkout)")
    p.add_argument("--timeout", type=float, default=120.0)
    p.add_argument("--out", default=str(OUT), help=f"the table (default {OUT.relative_to(REPO)})")
    p.add_argument("--executor", action="store_true",
                   help="only controller_executor's start-up on thesis Ex. 8 through a real master")
    args = p.parse_args(argv)

    ws = os.environ.get("LTL_STACK_WS")
    script = Path(ws, "devel", "lib", "ltl_stack", "synthesize") if ws else None
    if script is None or not script.exists():
        print("bench_cli_latency: source tools/env.sh first (no devel-space synthesize)", file=sys.stderr)
        return 2
    slugs = args.slugs if args.slugs and Path(args.slugs).is_file() and os.access(args.slugs, os.X_OK) else None
    if args.slugs and slugs is None:
        print(f"bench_cli_latency: {args.slugs} is not an executable; slugs column skipped", file=sys.stderr)
    rosrun = shutil.which("rosrun") if args.rosrun else None

    cache = tempfile.mkdtemp(prefix="bench-cli-pyc-")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPYCACHEPREFIX"] = cache
    if args.pythonpath:
        env["PYTHONPATH"] = os.pathsep.join([str(Path(args.pythonpath).resolve()), env.get("PYTHONPATH", "")])

    if args.executor:
        print("\n".join(executor_start(args.repeat, args.timeout, env)))
        shutil.rmtree(cache, ignore_errors=True)
        return 0
    specs = shared_specs() + generated_specs(args.generated)
    if args.only:
        specs = [s for s in specs if any(o in name_of(s) for o in args.only)]
    columns: dict[str, list[str]] = {"ours": [str(script)]}
    if slugs:
        columns["slugs"] = [slugs, "--sysInitRoboticsSemantics"]
    if rosrun:
        columns["rosrun"] = [rosrun, "ltl_stack", "synthesize"]
        columns["rosrun itself"] = [rosrun, "--prefix", "true", "ltl_stack", "synthesize"]

    run(columns["ours"] + [str(specs[0])], env, args.timeout)  # warm the bytecode cache
    started = time.time()
    rows = []
    for spec in specs:
        runs: dict[str, list[dict]] = {c: [] for c in columns}
        for _ in range(args.repeat):
            for column, cmd in columns.items():  # alternate, so drift hits every column alike
                runs[column].append(run(cmd + [str(spec)], env, args.timeout))
        row = {"spec": name_of(spec), "runs": runs}
        ours_v = {verdict_ours(r) for r in runs["ours"]}
        row["verdict"] = "/".join(sorted(ours_v))
        if slugs:
            slugs_v = {verdict_slugs(r) for r in runs["slugs"]}
            if slugs_v != ours_v:
                row["verdict"] += f" DIFFERENT (slugs {'/'.join(sorted(slugs_v))})"
        rows.append(row)
        print(f"{row['spec']}: " + ", ".join(f"{c} {ms(med(runs[c], 'wall'))} ms" for c in columns),
              file=sys.stderr, flush=True)

    head = ["spec", "realizable", "ours wall ms", "ours CPU ms"]
    if slugs:
        head += ["slugs wall ms", "slugs CPU ms", "ours / slugs (wall)"]
    if rosrun:
        head += ["rosrun wall ms", "rosrun itself ms", "ours through rosrun, rosrun's own cost taken out, ms"]
        if slugs:
            head += ["that / slugs"]
    lines = ["# `synthesize` whole-process latency", "",
             f"Command: `python test/benchmarks/bench_cli_latency.py{' --slugs SLUGS' if slugs else ''} "
             f"--repeat {args.repeat}{f' --generated {args.generated:g}' if args.generated else ''}"
             f"{' --pythonpath ' + args.pythonpath if args.pythonpath else ''}`, "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(started))}, {platform.machine()}, "
             f"{os.cpu_count()} cores shared with other jobs (load average at the start "
             f"{os.getloadavg()[0]:.1f}). Medians of {args.repeat} alternating runs per column; "
             "realizability only, robotics init semantics on both sides.", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    summary = {"over": [], "slower_than_slugs_over_100ms": []}
    for row in rows:
        runs = row["runs"]
        ours, ours_cpu = med(runs["ours"], "wall"), med(runs["ours"], "cpu")
        cells = [f"`{row['spec']}`", row["verdict"], ms(ours), ms(ours_cpu)]
        slugs_wall = med(runs["slugs"], "wall") if slugs else None
        if slugs:
            ratio = ours / slugs_wall if ours and slugs_wall else None
            cells += [ms(slugs_wall), ms(med(runs["slugs"], "cpu")), "–" if ratio is None else f"{ratio:.2f}"]
            if ratio is not None and ratio > 1.5:
                summary["over"].append(row["spec"])
            if ratio is not None and slugs_wall > 0.1 and ratio >= 1:
                summary["slower_than_slugs_over_100ms"].append(row["spec"])
        if rosrun:
            total, own = med(runs["rosrun"], "wall"), med(runs["rosrun itself"], "wall")
            share = total - own if total is not None and own is not None else None
            cells += [ms(total), ms(own), ms(share)]
            if slugs:
                cells.append("–" if share is None or not slugs_wall else f"{share / slugs_wall:.2f}")
        lines.append("| " + " | ".join(cells) + " |")
    if slugs:
        lines += ["", f"Over 1.5× slugs (wall): {', '.join(summary['over']) or 'none'}. "
                      f"Not faster than slugs where slugs needs > 100 ms: "
                      f"{', '.join(summary['slower_than_slugs_over_100ms']) or 'none'}."]
    lines += ["", f"Total benchmark time {time.time() - started:.0f} s.", ""]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines))
    print("\n".join(lines))
    shutil.rmtree(cache, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

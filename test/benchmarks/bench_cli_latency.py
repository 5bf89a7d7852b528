"""Whole-process latency of ``synthesize`` as a user runs it, against slugs in the same run.

    python test/benchmarks/bench_cli_latency.py --slugs SLUGS
    python test/benchmarks/bench_cli_latency.py --slugs PATH --generated 1.0   # + generated members up to 1 s
    python test/benchmarks/bench_cli_latency.py --pythonpath /tmp/old/src      # an older checkout's code
    python test/benchmarks/bench_cli_latency.py --check-share --before /tmp/main/src   # the vacuity check's share

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

``--check-share`` measures, on the large realizable games of the synthesis benchmark, what the
default command costs beside the solve alone: ``synthesize SPEC --json`` (verdict, then the vacuity
check) and a process that only solves (``synthesize(spec, strategy=False)``), each a whole process
(CPU of the child), minus the start-up of a process that imports the command and does nothing. With
``--before SRC`` the command also runs with an older checkout's sources first on ``PYTHONPATH``, in
the same alternating rounds, and the two checks' answers (``vacuity``, ``assumptions_satisfiable``)
are compared. Table: ``docs/benchmarks/check_share.md``.
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
#: ``../shared/specs`` beside the repository
SHARED = REPO.parent / "shared" / "specs"
OUT = REPO / "docs" / "benchmarks" / "cli_latency.md"
CHECK_SHARE_OUT = REPO / "docs" / "benchmarks" / "check_share.md"
#: the realizable games of the synthesis benchmark on which the vacuity check's share is measured
#: (``grid:n:k:m`` is ``bench_synthesis_family.grid_patrol``, written as .slugsin for the command)
CHECK_SHARE_GAMES = [
    "clean_and_patrol", "two_customer_waiter_txt", "cinderella_stepmother_n6c2_14_by_6",
    "cinderella_stepmother_n6c1_15_by_5", "grid:16:4:3", "moving_obstacle_24x24_7glitches",
    "moving_obstacle_32x32_11glitches", "factory_assembly_5x5_2_0errors", "factory_assembly_5x5_2_1errors",
    "factory_assembly_5x6_2_0errors", "factory_assembly_7x5_2_0errors", "grid:32:4:3", "basicEvasion",
    "factory_assembly_5x5_2_10errors", "factory_assembly_5x5_2_11errors"]
#: a process that solves only: the command's own solve, without the check after it
#: (started as the script starts: the collector off while importing, no teardown at the end)
SOLVE_ONLY = ("import gc; gc.disable(); import sys; from ltl_stack import cli; from ltl_stack.spec.load import "
              "load_spec; from ltl_stack.synthesis import synthesize; import ltl_stack.synthesis.cli; "
              "cli.imports_done(); cli.exit_now(0 if synthesize(load_spec(sys.argv[1]), strategy=False).realizable "
              "else 10)")
START_UP = ("import gc; gc.disable(); from ltl_stack import cli; import ltl_stack.synthesis.cli; cli.imports_done(); "
            "cli.exit_now(0)")
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
        proc.returncode = -os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status)
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


#: the executor's log lines that end a start-up phase (``--phases``), in order
PHASES = [("synthesizing ", "process start -> files read, node registered, params fetched"),
          ("synthesized in ", "synthesis"),
          ("running the ", "explicit strategy built")]


def log_phases(text: str, start: float) -> list[tuple[str, float]]:
    """When each phase ended, in seconds after ``start`` (wall clock), from rospy's ``[INFO] [t]: msg`` lines."""
    import re

    found = []
    for line in text.splitlines():
        m = re.match(r"\[INFO\] \[(\d+\.\d+)\]: \S+: (.*)", line)
        if m:
            for prefix, name in PHASES:
                if m.group(2).startswith(prefix) and name not in dict(found):
                    found.append((name, float(m.group(1)) - start))
    return found


def executor_start(repeat: int, timeout: float, env: dict[str, str], phases: bool = False) -> list[str]:
    """``controller_executor`` on thesis Ex. 8 (config/clean_and_patrol) through a real master: from
    starting the process to its first ``~state`` with a state (latched; received by a subscriber
    started before it), the robot assumed in topLane and every other input false (``--init-props``), so no sensor node is needed.
    With ``phases``, the node's own log says when its start-up phases ended."""
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
    phase_times: dict[str, list[float]] = {}
    try:
        for k in range(repeat + 1):  # the first run only warms the bytecode cache
            first.clear()
            log = tempfile.TemporaryFile()
            wall_start = time.time()
            start = time.perf_counter()
            proc = subprocess.Popen([str(script), str(spec), str(config / "clean_and_patrol.yaml"), "--init-props",
                                     ",".join(f"{v}={int(v == 'topLane_rc')}" for v in inputs)], env=env,
                                    stdout=log, stderr=subprocess.STDOUT)
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
            log.seek(0)
            if k and phases:
                for name, at in log_phases(log.read().decode(errors="replace"), wall_start):
                    phase_times.setdefault(name, []).append(at)
            log.close()
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
    lines = [line]
    if phase_times:
        lines += [f"  phase ended (median after process start): {name} {statistics.median(v) * 1000:.0f} ms"
                  for name, v in phase_times.items()]
        lines.append(f"  first ~state received {statistics.median(times) * 1000:.0f} ms")
    return lines


def main(argv: list[str] | None = None) -> int:
    # every run measures a cold start: a variable order saved by the run before (order_cache) would
    # make the second repeat of a spec cheaper than the first
    os.environ.setdefault("LTL_STACK_ORDER_CACHE", "off")
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--slugs", help="the slugs binary (built from source); without it the slugs column is skipped")
    p.add_argument("--repeat", type=int, default=5, help="runs per column and spec (median; default 5)")
    p.add_argument("--rosrun", action="store_true", default=True,
                   help="also run through rosrun and measure rosrun's own cost (default on; --no-rosrun: not)")
    p.add_argument("--no-rosrun", dest="rosrun", action="store_false", help=argparse.SUPPRESS)
    p.add_argument("--generated", type=float, default=0.0, metavar="S",
                   help="also the generated family members where slugs needs at most S seconds")
    p.add_argument("--only", nargs="+", metavar="NAME", help="only the specs whose name contains one of these")
    p.add_argument("--pythonpath", help="put this source folder first on PYTHONPATH (measure another checkout)")
    p.add_argument("--timeout", type=float, default=120.0)
    p.add_argument("--out", default=str(OUT), help=f"the table (default {OUT.relative_to(REPO)})")
    p.add_argument("--variants", action="store_true", default=True,
                   help="also ours without .pyc and without .pth files (python -S), and the start-up floor "
                        "(default on; --no-variants: not)")
    p.add_argument("--no-variants", dest="variants", action="store_false", help=argparse.SUPPRESS)
    p.add_argument("--executor", action="store_true",
                   help="only controller_executor's start-up on thesis Ex. 8 through a real master")
    p.add_argument("--phases", action="store_true",
                   help="with --executor: also print when each start-up phase ended in the node (from its log)")
    p.add_argument("--check-share", action="store_true",
                   help="only the vacuity check's share of the default command on the large games")
    p.add_argument("--before", metavar="SRC",
                   help="with --check-share: also the command with this checkout's sources (e.g. main's src)")
    p.add_argument("--before-once", type=float, default=120.0, metavar="S",
                   help="with --before: run the older command once only on a game where its first run took "
                        "more than S s CPU (default 120)")
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

    if args.check_share:
        out = Path(args.out) if args.out != str(OUT) else CHECK_SHARE_OUT
        lines = check_share(script, env, args, Path(cache), out)
        out.write_text("\n".join(lines))
        print("\n".join(lines))
        shutil.rmtree(cache, ignore_errors=True)
        return 0
    if args.executor:
        lines = executor_start(args.repeat, args.timeout, env, phases=args.phases)
        print("\n".join(lines))
        section = [EXECUTOR_HEADING, "", f"Command: `python test/benchmarks/bench_cli_latency.py --executor "
                   f"--repeat {args.repeat}{' --phases' if args.phases else ''}`, "
                   f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. The node's own log gives the phases; "
                   "the first `~state` is taken when the benchmark's subscriber receives it.", "",
                   *[f"- {line.strip()}" for line in lines], ""]
        write_sections(Path(args.out), executor=section)
        shutil.rmtree(cache, ignore_errors=True)
        return 0
    specs = shared_specs() + [ex8_slugsin(Path(cache))] + generated_specs(args.generated)
    if args.only:
        specs = [s for s in specs if any(o in name_of(s) for o in args.only)]
    columns: dict[str, tuple[list[str], dict[str, str]]] = {"ours": ([str(script)], env)}
    if slugs:
        columns["slugs"] = ([slugs, "--sysInitRoboticsSemantics"], env)
    run(columns["ours"][0] + [str(specs[0])], env, args.timeout)  # warm the bytecode cache
    if args.variants:
        run([sys.executable, "-S", str(script), str(specs[0])], no_site_env(env), args.timeout)
        columns["ours, no .pyc"] = ([str(script)], no_pyc_env(env, Path(cache)))
        columns["ours, no .pth"] = ([sys.executable, "-S", str(script)], no_site_env(env))
    if rosrun:
        columns["rosrun"] = ([rosrun, "ltl_stack", "synthesize"], env)
        columns["rosrun itself"] = ([rosrun, "--prefix", "true", "ltl_stack", "synthesize"], env)
    floor = start_up_floor(env, args.repeat, args.timeout) if args.variants else []
    started = time.time()
    load_start = os.getloadavg()[0]
    rows = []
    for spec in specs:
        runs: dict[str, list[dict]] = {c: [] for c in columns}
        for _ in range(args.repeat):
            for column, (cmd, cenv) in columns.items():  # alternate, so drift hits every column alike
                runs[column].append(run(cmd + [str(spec)], cenv, args.timeout))
        row = {"spec": name_of(spec), "runs": runs}
        ours_v = {verdict_ours(r) for r in runs["ours"]}
        row["verdict"] = "/".join(sorted(ours_v))
        for variant in ("ours, no .pyc", "ours, no .pth"):
            if variant in runs and {verdict_ours(r) for r in runs[variant]} != ours_v:
                row["verdict"] += f" DIFFERENT ({variant})"
        if slugs:
            slugs_v = {verdict_slugs(r) for r in runs["slugs"]}
            if slugs_v != ours_v:
                row["verdict"] += f" DIFFERENT (slugs {'/'.join(sorted(slugs_v))})"
        rows.append(row)
        print(f"{row['spec']}: " + ", ".join(f"{c} {ms(med(runs[c], 'cpu'))} ms CPU" for c in columns),
              file=sys.stderr, flush=True)
    lines = table(rows, args, slugs=bool(slugs), rosrun=bool(rosrun), started=started, load=load_start)
    if floor:
        lines += ["## Where a small run's CPU time goes", "",
                  f"Same run, medians of {args.repeat}: what a Python process costs before any of our work "
                  "(`.pyc` cached).", "", "| process | wall ms | CPU ms |", "|---|---|---|"]
        lines += [f"| {name} | {ms(med(r, 'wall'))} | {ms(med(r, 'cpu'))} |" for name, r in floor] + [""]
    lines += [f"Total benchmark time {time.time() - started:.0f} s; load average at the end "
              f"{os.getloadavg()[0]:.1f}.", ""]
    write_sections(Path(args.out), synthesize=lines)
    print("\n".join(lines))
    shutil.rmtree(cache, ignore_errors=True)
    shutil.rmtree(cache + "-without-ours", ignore_errors=True)
    return 0


def check_share_spec(name: str, folder: Path) -> Path:
    """The file of a game of ``CHECK_SHARE_GAMES`` (a grid patrol member is written to ``folder``)."""
    if name.startswith("grid:"):
        sys.path.insert(0, str(HERE))
        from bench_synthesis_family import grid_patrol

        from ltl_stack.spec import write_slugsin

        n, k, m = (int(v) for v in name.split(":")[1:])
        path = folder / f"grid_patrol_{n}_{k}_{m}.slugsin"
        path.write_text(write_slugsin(grid_patrol(n, k, m)))
        return path
    if name == "clean_and_patrol":
        return ex8_slugsin(folder)
    for path in [SHARED / "benchmarks" / "generated" / f"{name}.slugsin",
                 SHARED / "benchmarks" / "slugsin" / f"{name}.slugsin"]:
        if path.exists():
            return path
    raise SystemExit(f"bench_cli_latency: no spec named {name}")


def answers(r: dict) -> str:
    """The vacuity answers of one ``synthesize --json`` run, for comparing two checkouts."""
    import json

    try:
        summary = json.loads(r.get("out", "")[r.get("out", "").index("{"):])
    except ValueError:
        return f"exit {r.get('code', '?')}" if "timeout" not in r else "timeout"
    return f"{summary.get('assumptions_satisfiable')} {summary.get('vacuity')}"


def check_share(script: Path, env: dict[str, str], args: argparse.Namespace, folder: Path, out: Path) -> list[str]:
    """The default command against the solve alone (whole processes, CPU), before and after; the
    table so far is written to ``out`` after every game."""
    before_env = None
    if args.before:
        before_env = dict(env, PYTHONPATH=os.pathsep.join([str(Path(args.before).resolve()), env.get("PYTHONPATH", "")]))
    names = CHECK_SHARE_GAMES
    if args.only:
        names = [n for n in names if any(o in n for o in args.only)]
    py = sys.executable
    columns: dict[str, tuple[list[str], dict[str, str]]] = {
        "command": ([str(script)], env), "solve": ([py, "-c", SOLVE_ONLY], env)}
    if before_env:
        columns["before"] = ([str(script)], before_env)
    run([str(script), str(check_share_spec("clean_and_patrol", folder))], env, args.timeout)  # warm .pyc
    if before_env:
        run([str(script), str(check_share_spec("clean_and_patrol", folder))], before_env, args.timeout)
    start_up = {key: [run([py, "-c", START_UP], e, args.timeout) for _ in range(args.repeat)]
                for key, e in (("after", env), ("before", before_env)) if e}
    floor = {key: med(r, "cpu") or 0.0 for key, r in start_up.items()}
    started, load = time.time(), os.getloadavg()[0]
    rows = []
    for name in names:
        spec = str(check_share_spec(name, folder))
        runs: dict[str, list[dict]] = {c: [] for c in columns}
        for k in range(args.repeat):
            for column, (cmd, cenv) in columns.items():
                if column == "before" and k and runs[column] and runs[column][0].get("cpu", 1e9) > args.before_once:
                    continue
                extra = ["--json"] if column != "solve" else []
                runs[column].append(run(cmd + [spec] + extra, cenv, args.timeout))
        rows.append((name, runs))
        print(f"{name}: " + ", ".join(f"{c} {med(r, 'cpu') or 0:.2f} s CPU ({len(r)} runs)" for c, r in runs.items()),
              file=sys.stderr, flush=True)
        out.write_text("\n".join(check_share_table(rows, args, floor, started, load)))  # so far
    return check_share_table(rows, args, floor, started, load)


def check_share_table(rows: list, args: argparse.Namespace, floor: dict[str, float], started: float,
                      load: float) -> list[str]:
    before = "before" in floor
    head = ["game", "realizable", "solve alone, CPU s", "command, CPU s", "command / solve", "check's share"]
    if before:
        head += ["command before, CPU s (runs)", "before / solve", "same answers"]
    lines = ["# The vacuity check's share of `synthesize SPEC`", "",
             f"Command: `python test/benchmarks/bench_cli_latency.py {command_line(args)}`, "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(started))}, {platform.machine()}, {os.cpu_count()} "
             f"cores shared with other jobs (load average {load:.1f} at the start, {os.getloadavg()[0]:.1f} at the "
             f"end). Whole processes, CPU (user + system of the child), medians of {args.repeat} alternating runs "
             "unless the runs column says fewer. *command*: `synthesize SPEC --json` (realizability, then the "
             "vacuity check); *solve alone*: a process that only calls `synthesize(spec, strategy=False)`; both "
             f"minus the start-up of a process importing the command ({floor.get('after', 0.0) * 1000:.0f} ms CPU"
             + (f", {floor['before'] * 1000:.0f} ms with the older sources" if before else "") + "). *command / "
             "solve* = (command − start-up) / (solve − start-up); *check's share* = (command − solve) / "
             "(solve − start-up)." + (" *before*: the same command with the older sources first on "
                                     "`PYTHONPATH` (`--before`); the solve's algorithm is the same in both." if before
                                     else ""), "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    ratios = []
    for name, runs in rows:
        solve, command = med(runs["solve"], "cpu"), med(runs["command"], "cpu")
        verdicts = "/".join(sorted({verdict_ours(r) for r in runs["command"]}))
        base = solve - floor["after"] if solve is not None else None
        ratio = (command - floor["after"]) / base if command is not None and base else None
        share = (command - solve) / base if command is not None and base else None
        if ratio is not None:
            ratios.append((ratio, name))
        cells = [f"`{name}`", verdicts, _secs(solve), _secs(command), _ratio(ratio),
                 "–" if share is None else f"{share * 100:.0f} %"]
        if before:
            old = med(runs["before"], "cpu")
            old_ratio = (old - floor["before"]) / base if old is not None and base else None
            same = {answers(r) for r in runs["before"]} == {answers(r) for r in runs["command"]}
            cells += [f"{_secs(old)} ({len(runs['before'])})", _ratio(old_ratio), "yes" if same else
                      f"**no**: {sorted({answers(r) for r in runs['command']})} vs "
                      f"{sorted({answers(r) for r in runs['before']})}"]
        lines.append("| " + " | ".join(cells) + " |")
    if ratios:
        worst = max(ratios)
        lines += ["", f"Largest command / solve: {worst[0]:.2f} ({worst[1]}); over 1.25: "
                      f"{', '.join(n for r, n in ratios if r > 1.25) or 'none'}."]
    return lines + [""]


def _secs(value: float | None) -> str:
    return "–" if value is None else f"{value:.2f}"


EXECUTOR_HEADING = "## `controller_executor` start-up"


def write_sections(out: Path, synthesize: list[str] | None = None, executor: list[str] | None = None) -> None:
    """Write the table file; the part a run does not measure (the synthesize tables or the executor
    section) is kept from the file as it was."""
    old = out.read_text() if out.exists() else ""
    head, _, tail = old.partition(EXECUTOR_HEADING)
    old_executor = (EXECUTOR_HEADING + tail).splitlines() if tail else []
    text = "\n".join(synthesize if synthesize is not None else head.rstrip("\n").splitlines())
    text = text.rstrip("\n") + "\n\n" + "\n".join(executor if executor is not None else old_executor)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text.rstrip("\n") + "\n")


def ex8_slugsin(folder: Path) -> Path:
    """Thesis Example 8 as the executor runs it (``config/clean_and_patrol``), written as ``.slugsin``
    so that both tools read the same file."""
    from ltl_stack.spec import load_spec, write_slugsin

    path = folder / "clean_and_patrol.slugsin"
    path.write_text(write_slugsin(load_spec(REPO / "config" / "clean_and_patrol" / "clean_and_patrol.structuredslugs")))
    return path


def no_pyc_env(env: dict[str, str], cache: Path) -> dict[str, str]:
    """Our sources compiled on every run (a source checkout under ``PYTHONDONTWRITEBYTECODE`` whose
    ``.pyc`` nobody wrote): a copy of the warmed bytecode folder without our package's sources, which
    is not written to. Every other module (stdlib, venv, generated messages) keeps its ``.pyc``."""
    bare = cache.parent / (cache.name + "-without-ours")
    if not bare.exists():
        shutil.copytree(cache, bare)
        for folder in [d for d in bare.rglob("ltl_stack") if d.is_dir() and d.parent.name == "src"]:
            shutil.rmtree(folder, ignore_errors=True)
    return dict(env, PYTHONDONTWRITEBYTECODE="1", PYTHONPYCACHEPREFIX=str(bare))


def no_site_env(env: dict[str, str]) -> dict[str, str]:
    """``python -S`` with the same ``sys.path``: no ``site`` module, so no ``.pth`` file runs — on this
    machine a sandbox ``.pth`` imports certifi in every Python process, which a user's machine does not."""
    import site

    dirs = [d for d in site.getsitepackages() if Path(d).is_dir()]
    return dict(env, PYTHONPATH=os.pathsep.join([env.get("PYTHONPATH", ""), *dirs]))


def start_up_floor(env: dict[str, str], repeat: int, timeout: float) -> list[tuple[str, list[dict]]]:
    """The bare interpreter, with and without ``site`` (.pth files), and the imports of a verdict run."""
    py = sys.executable
    nosite = no_site_env(env)
    cases = [("`python -c pass` (venv, site and .pth files)", [py, "-c", "pass"], env),
             ("`python -S -c pass` (no site, no .pth)", [py, "-S", "-c", "pass"], nosite),
             ("`/usr/bin/python3 -c pass` (system python, its site)", ["/usr/bin/python3", "-c", "pass"], env),
             ("`python -c 'import ltl_stack.synthesis.cli'`", [py, "-c", "import ltl_stack.synthesis.cli"], env),
             ("`python -S -c 'import ltl_stack.synthesis.cli'`", [py, "-S", "-c", "import ltl_stack.synthesis.cli"],
              nosite),
             ("`python -S -c 'import ltl_stack.synthesis.game'` (dd.cudd and the spec model)",
              [py, "-S", "-c", "import ltl_stack.synthesis.game"], nosite),
             ("`python -S -c 'import dd.cudd'` (networkx hidden, as `synthesis.game` does: dd's own floor)",
              [py, "-S", "-c", "import sys; sys.modules['networkx'] = None; import dd.cudd"], nosite),
             ("`python -S -c 'gc.disable(); import ltl_stack.synthesis.cli; os._exit(0)'` (what the script "
              "pays for its imports: no collection while loading, no teardown)",
              [py, "-S", "-c", "import gc; gc.disable(); import os, ltl_stack.synthesis.cli; os._exit(0)"], nosite)]
    runs: dict[str, list[dict]] = {name: [] for name, _, _ in cases}
    for _ in range(repeat):
        for name, cmd, cenv in cases:
            if Path(cmd[0]).exists():
                runs[name].append(run(cmd, cenv, timeout))
    return [(name, r) for name, r in runs.items() if r]


def table(rows: list[dict], args: argparse.Namespace, *, slugs: bool, rosrun: bool, started: float,
          load: float) -> list[str]:
    variants = args.variants
    head = ["spec", "realizable", "ours wall ms", "ours CPU ms"]
    if slugs:
        head += ["slugs wall ms", "slugs CPU ms", "ours / slugs (wall)", "ours / slugs (CPU)"]
    if variants:
        head += ["ours, no .pyc: CPU ms", "ours, no .pth: CPU ms"]
        if slugs:
            head += ["no .pth / slugs (CPU)"]
    if rosrun:
        head += ["rosrun wall ms", "rosrun itself ms", "ours through rosrun, rosrun's own cost taken out, ms"]
        if slugs:
            head += ["that / slugs"]
    lines = ["# `synthesize` whole-process latency", "",
             f"Command: `python test/benchmarks/bench_cli_latency.py {command_line(args)}`, "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime(started))}, {platform.machine()}, "
             f"{os.cpu_count()} cores shared with other jobs (load average at the start {load:.1f}). "
             f"Medians of {args.repeat} alternating runs per column; realizability only, robotics init "
             "semantics on both sides; CPU is user + system time of the process and its children "
             "(`os.wait4`), the steadier figure on a loaded machine. `clean_and_patrol` is thesis Ex. 8 as "
             "`config/clean_and_patrol` has it, written as .slugsin for both tools (the shared README calls "
             "`move_group_and_move_base` Ex. 8).", ""]
    if variants:
        lines += ["Variants of ours: *no .pyc* compiles our sources on every run (a source checkout under "
                  "`PYTHONDONTWRITEBYTECODE`, as the devel space is in this environment unless the bootstrap "
                  "compiles it); *no .pth* runs the same script with `python -S` and the same `sys.path`, "
                  "so no `.pth` file runs — this machine's sandbox puts one in the system site-packages "
                  "that imports certifi in every Python process (~25 ms CPU of a bare interpreter, but most "
                  "of what it imports — re, pathlib, typing — our imports need anyway), which a user's "
                  "machine does not have.", ""]
    lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    summary: dict[str, list] = {"over": [], "over_cpu": [], "slow": [], "slow_cpu": [], "cpu_ratios": [],
                                "nopth_ratios": [], "over_nopth": []}
    for row in rows:
        runs = row["runs"]
        ours, ours_cpu = med(runs["ours"], "wall"), med(runs["ours"], "cpu")
        cells = [f"`{row['spec']}`", row["verdict"], ms(ours), ms(ours_cpu)]
        slugs_wall = med(runs["slugs"], "wall") if slugs else None
        slugs_cpu = med(runs["slugs"], "cpu") if slugs else None
        if slugs:
            ratio = ours / slugs_wall if ours and slugs_wall else None
            cpu_ratio = ours_cpu / slugs_cpu if ours_cpu and slugs_cpu else None
            cells += [ms(slugs_wall), ms(slugs_cpu), _ratio(ratio), _ratio(cpu_ratio)]
            if ratio is not None and ratio > 1.5:
                summary["over"].append(row["spec"])
            if cpu_ratio is not None:
                summary["cpu_ratios"].append(cpu_ratio)
                if cpu_ratio > 1.5:
                    summary["over_cpu"].append(row["spec"])
            if ratio is not None and slugs_wall > 0.1 and ratio >= 1:
                summary["slow"].append(row["spec"])
            if cpu_ratio is not None and slugs_cpu > 0.1 and cpu_ratio >= 1:
                summary["slow_cpu"].append(row["spec"])
        if variants:
            nopth = med(runs["ours, no .pth"], "cpu")
            cells += [ms(med(runs["ours, no .pyc"], "cpu")), ms(nopth)]
            if slugs:
                nopth_ratio = nopth / slugs_cpu if nopth and slugs_cpu else None
                cells.append(_ratio(nopth_ratio))
                if nopth_ratio is not None:
                    summary["nopth_ratios"].append(nopth_ratio)
                    if nopth_ratio > 1.5:
                        summary["over_nopth"].append(row["spec"])
        if rosrun:
            total, own = med(runs["rosrun"], "wall"), med(runs["rosrun itself"], "wall")
            share = total - own if total is not None and own is not None else None
            cells += [ms(total), ms(own), ms(share)]
            if slugs:
                cells.append("–" if share is None or not slugs_wall else f"{share / slugs_wall:.2f}")
        lines.append("| " + " | ".join(cells) + " |")
    if slugs:
        n = len(rows)
        lines += ["", f"Over 1.5× slugs: wall {len(summary['over'])} of {n} specs, CPU {len(summary['over_cpu'])} "
                      f"of {n} ({', '.join(summary['over_cpu']) or 'none'}). Not faster than slugs where slugs "
                      f"needs > 100 ms: wall {', '.join(summary['slow']) or 'none'}; CPU "
                      f"{', '.join(summary['slow_cpu']) or 'none'}."]
        if summary["cpu_ratios"]:
            lines[-1] += (f" CPU ours / slugs: median {statistics.median(summary['cpu_ratios']):.2f} "
                          f"({min(summary['cpu_ratios']):.2f}–{max(summary['cpu_ratios']):.2f}).")
        if summary["nopth_ratios"]:
            lines[-1] += (f" Without the sandbox's .pth (no .pth column): median "
                          f"{statistics.median(summary['nopth_ratios']):.2f} "
                          f"({min(summary['nopth_ratios']):.2f}–{max(summary['nopth_ratios']):.2f}), over 1.5×: "
                          f"{len(summary['over_nopth'])} of {n}.")
    return lines + [""]


def command_line(args: argparse.Namespace) -> str:
    """The benchmark's arguments as given, the slugs binary's path shown as SLUGS."""
    shown = ["SLUGS" if args.slugs and a == args.slugs else a for a in sys.argv[1:]]
    return " ".join(shown) or f"--repeat {args.repeat}"


def _ratio(value: float | None) -> str:
    return "–" if value is None else f"{value:.2f}"


if __name__ == "__main__":
    sys.exit(main())

"""Code-transfer timing per thesis example (on demand), beside Table 2.5's figures.

    python -m pytest test/benchmarks/bench_transfer.py -q -s      (or: python test/benchmarks/bench_transfer.py)

Per example: the median of 5 in-process transfers (robot files re-read each time, URDF caches
cleared) and one fresh ``ros_code_transfer`` process (interpreter start and imports included).
Peers in the same run: ``ast.parse`` of the same program (the least an AST-based transfer must do) for
every example, and, for joint retargeting, the same objective minimised by L-BFGS-B with
finite-difference gradients (scipy's default) instead of SLSQP with the analytic gradient.
Figures go to docs/benchmarks/transfer.md.
"""
from __future__ import annotations

import ast
import os
import statistics
import subprocess
import sys
import time
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
DATA = ROOT / "test" / "data" / "transfer"
OUT = ROOT / "docs" / "benchmarks" / "transfer.md"

# (label, program, source, target, uses codebase, Table 2.5 seconds)
EXAMPLES = [
    ("Example 1: keyboard control, Jackal -> Turtlebot", "keyboard_jackal.py", "jackal", "turtlebot", True, 2.9),
    ("Example 2: obstacle avoidance, Turtlebot -> Jackal", "wander_turtlebot.py", "turtlebot", "jackal", True, 1.4),
    ("Example 3: joint trajectory, UR5 -> Jaco 6 DoF", "follow_trajectory_ur5.py", "ur5", "j2n6s300", False, 11.7),
    ("Example 3: joint trajectory, UR5 -> Jaco 7 DoF", "follow_trajectory_ur5.py", "ur5", "j2s7s300", False, 11.7),
    ("Example 4: greet, Pepper -> NAO", "greet_pepper.py", "pepper", "nao", False, 3.3),
    ("Example 5: MoveIt, Fetch -> PR2", "moveit_fetch.py", "fetch", "pr2", False, 2.8),
    ("Example 6: localization, unknown -> Turtlebot", "localization.py", "unknown", "turtlebot", True, 10.08),
    ("Example 6: localization, unknown -> Jackal", "localization.py", "unknown", "jackal", True, 8.74),
]


def median_seconds(action, repeats: int = 5) -> float:
    return statistics.median(timeit.repeat(action, number=1, repeat=repeats))


def run_once(program, source, target, codebase):
    from ltl_stack.transfer import urdf
    from ltl_stack.transfer.codebase import load_codebase
    from ltl_stack.transfer.profiles import load_profile
    from ltl_stack.transfer.transfer import TransferOptions, transfer_program

    urdf._load_cached.cache_clear()
    urdf._tree_cached.cache_clear()
    robots = SHARED / "robots"
    stats = load_codebase(SHARED / "codebase" / "channel_counts.yaml", target) if codebase else None
    text = (DATA / program).read_text()
    return transfer_program(text, load_profile(robots, source, allow_unknown=True), load_profile(robots, target),
                            TransferOptions(stats=stats), filename=program)


def fresh_process_seconds(program, source, target, codebase, tmp: Path) -> float:
    args = [sys.executable, "-c", "import sys; from ltl_stack.transfer.cli import main; sys.exit(main())",
            str(DATA / program), "--from", source, "--to", target, "--robots", str(SHARED / "robots"),
            "-o", str(tmp / "out.py"), "--non-interactive", "-q"]
    if codebase:
        args += ["--codebase", str(SHARED / "codebase" / "channel_counts.yaml")]
    start = time.perf_counter()
    done = subprocess.run(args, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    assert done.returncode in (0, 1), done.stderr
    return seconds


def finite_difference_peer(program, source, target):
    """The same retargeting with L-BFGS-B and numerical gradients (the naive way)."""
    import scipy.optimize

    from ltl_stack.transfer import retarget

    original = retarget.minimize

    def naive(fun, x0, args=(), jac=None, method=None, bounds=None, options=None):
        return scipy.optimize.minimize(lambda q, *a: fun(q, *a)[0], x0, args=args, method="L-BFGS-B",
                                       bounds=bounds)

    retarget.minimize = naive
    try:
        return median_seconds(lambda: run_once(program, source, target, False), repeats=3), \
            run_once(program, source, target, False)
    finally:
        retarget.minimize = original


def run_benchmark(tmp: Path) -> str:
    run_once(*EXAMPLES[2][1:5])  # import yourdfpy once: not part of any example's figure
    rows, peers = [], []
    for label, program, source, target, codebase, thesis in EXAMPLES:
        seconds = median_seconds(lambda p=program, s=source, t=target, c=codebase: run_once(p, s, t, c))
        result = run_once(program, source, target, codebase)
        text = (DATA / program).read_text()
        parse = median_seconds(lambda text=text: ast.parse(text), repeats=20)
        fresh = fresh_process_seconds(program, source, target, codebase, tmp)
        s = result.report.summary()
        extra = ""
        if result.report.retargeting:
            errors = [p["ee_error_m"] * 1000 for p in result.report.retargeting["points"]]
            extra = f"max end-effector error {max(errors):.1f} mm"
            peer, peer_result = finite_difference_peer(program, source, target)
            peer_errors = [p["ee_error_m"] * 1000 for p in peer_result.report.retargeting["points"]]
            peers.append(f"| {label} | {seconds:.3f} | {peer:.3f} | {peer / seconds:.1f}x | "
                         f"{max(errors):.1f} | {max(peer_errors):.1f} |")
        rows.append(f"| {label} | {thesis} | {seconds:.3f} | {fresh:.2f} | {seconds / parse:.0f}x | "
                    f"{s['channels_replaced']} | {s['parameters_replaced']} | {s['unresolved']} | {extra} |")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return "\n".join([
        "# Code transfer timing (thesis Table 2.5)",
        "",
        "Produced by `python -m pytest test/benchmarks/bench_transfer.py -q -s` on a shared 2-core machine "
        f"under load (1-minute load average {load:.1f} at the end of the run); figures vary run to run.",
        "",
        "*in-process*: median of 5 transfers, robot files re-read (URDF caches cleared), yourdfpy already "
        "imported. *fresh process*: one `ros_code_transfer` run including Python start-up and imports "
        "(every transfer imports yourdfpy and scipy, 1-1.5 s together on this machine: imports are at module "
        "top). *vs ast.parse*: in-process time divided by the time to parse the same program — the peer "
        "every AST-based transfer pays. Non-interactive, no live master or listing (action names stay "
        "unresolved here; `python -m ltl_stack.transfer.thesis_table` and the integration tests choose "
        "them). Goals: under 1 s for channel/velocity examples, under 3 s for joint retargeting.",
        "",
        "| example | Table 2.5 (s) | in-process (s) | fresh process (s) | vs ast.parse | channels | "
        "parameters | unresolved | |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        *rows,
        "",
        "## Joint retargeting: analytic gradient (SLSQP) vs finite differences (L-BFGS-B)",
        "",
        "Same objective, bounds, weights and warm starts; only the optimiser differs (median of 3).",
        "",
        "| example | SLSQP + gradient (s) | L-BFGS-B, numerical gradient (s) | ratio | max EE error (mm) | "
        "peer max EE error (mm) |",
        "| --- | --- | --- | --- | --- | --- |",
        *peers,
        "",
    ])


def test_transfer_benchmark(tmp_path):
    if not (SHARED / "robots").is_dir():
        import pytest

        pytest.skip(f"{SHARED / 'robots'} is absent")
    text = run_benchmark(tmp_path)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(text)
    print(text)


if __name__ == "__main__":
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        report = run_benchmark(Path(tmp))
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(report)
    print(report)

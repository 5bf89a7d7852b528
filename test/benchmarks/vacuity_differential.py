"""The vacuity check against its first implementation on the large shared games (run on demand).

    python test/benchmarks/vacuity_differential.py [--timeout S] [NAME ...]

The unit test ``test_vacuity_differential`` compares the two on every shared spec that solves in
seconds; this script does the same on the generated families and basicEvasion, where the reference
check alone takes minutes. Each game runs in a process of its own with a time limit: solve (the
command's realizability-only solve), then both checks as the command calls them (with the winning
positions, the new one also with the solve's ``cpre_winning``), and prints one line per game with
both answers and their CPU times.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
SHARED = REPO.parent / "shared" / "specs"


def one(path: str) -> dict:
    """Solve and compare both checks on one spec (runs in the worker process)."""
    import resource

    sys.path.insert(0, str(REPO / "test" / "unit" / "synthesis"))
    import vacuity_reference

    from ltl_stack.spec import load_spec
    from ltl_stack.synthesis import synthesize
    from ltl_stack.synthesis.vacuity import check

    def cpu() -> float:
        usage = resource.getrusage(resource.RUSAGE_SELF)
        return usage.ru_utime + usage.ru_stime

    t = cpu()
    result = synthesize(load_spec(path), strategy=False)
    row = {"spec": Path(path).stem, "realizable": result.realizable, "solve": round(cpu() - t, 2)}
    if not result.realizable:
        return row
    game, solution = result.game, result.solution
    t = cpu()
    new = check(game, solution.winning, cpre_winning=solution.cpre_winning)
    row["check"] = round(cpu() - t, 2)
    t = cpu()
    old = vacuity_reference.check(game, solution.winning)
    row["reference"] = round(cpu() - t, 2)
    row["same"] = new == old
    row["answers"] = [new.assumptions_satisfiable, new.assumptions_satisfiable_alone, list(new.warnings)]
    if new != old:
        row["reference_answers"] = [old.assumptions_satisfiable, old.assumptions_satisfiable_alone,
                                    list(old.warnings)]
    return row


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("names", nargs="*", help="only the games whose name contains one of these")
    p.add_argument("--timeout", type=float, default=600.0, help="per game, seconds (default 600)")
    p.add_argument("--worker", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.worker:
        print(json.dumps(one(args.worker)))
        return 0
    games = sorted((SHARED / "benchmarks" / "generated").glob("*.slugsin"))
    games.append(SHARED / "benchmarks" / "slugsin" / "basicEvasion.slugsin")
    if args.names:
        games = [g for g in games if any(n in g.stem for n in args.names)]
    different = 0
    for game in games:
        try:
            done = subprocess.run([sys.executable, __file__, "--worker", str(game)], capture_output=True,
                                  text=True, timeout=args.timeout)
            line = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else f"error: {done.stderr[-300:]}"
        except subprocess.TimeoutExpired:
            line = f"{game.stem}: not within {args.timeout:g} s"
        different += '"same": false' in line
        print(line, flush=True)
    print(f"{len(games)} games, {different} with different answers")
    return 1 if different else 0


if __name__ == "__main__":
    sys.exit(main())

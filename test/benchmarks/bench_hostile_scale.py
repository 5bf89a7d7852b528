"""Hostile-input scale (on demand): time and peak memory against input size, the code before the
fix as the peer in the same run.

    python test/benchmarks/bench_hostile_scale.py [--quick]

Each measurement is a fresh child process (peak memory is its ``ru_maxrss``), the median of 3 runs.
Items: the adjacency of an LTLMoP map of N thin "pie" slices (the old code tested every pair whose
boxes meet: all of them); Python 2 transfer of a program of N ``print`` statements (the old code copied the token list
once per statement); Structured English ``visit all G`` sentences over a group of M regions (the
old code made one goal per member and sentence; now at most ``MAX_REPEATED`` sentences are made and
the next is refused in one line). The old code is read from git (``BASE``) into a temporary folder.
Figures go to docs/BENCHMARKS.md ("Hostile input at scale").
"""
from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BASE = "b756579"  # main before the fixes

CHILD = r"""
import json, resource, sys, time
kind, size, module_dir = sys.argv[1], int(sys.argv[2]), sys.argv[3]
if kind == "print":
    if module_dir != "-":
        sys.path.insert(0, module_dir)
        import python2_old as mod
    else:
        from ltl_stack.transfer import python2 as mod
    text = "import sys\n" + "".join(f"print 'line', {i}\n" for i in range(size))
    t0 = time.process_time()
    mod.python2_parse_text(text, "p.py")
    seconds = time.process_time() - t0
    outcome = "ok"
elif kind == "pie":
    import math
    if module_dir != "-":
        sys.path.insert(0, module_dir)
        import region_map_old as mod
    else:
        from ltl_stack.spec import region_map as mod
    regions = [{"name": "Boundary", "type": "rect", "position": [-1100, -1100], "size": [2200, 2200]}]
    for i in range(size):
        a0, a1 = 2 * math.pi * i / size, 2 * math.pi * (i + 1) / size
        points = [[0, 0], [round(1000 * math.cos(a0), 6), round(1000 * math.sin(a0), 6)],
                  [round(1000 * math.cos(a1), 6), round(1000 * math.sin(a1), 6)]]
        regions.append({"name": f"s{i}", "type": "poly", "position": [0, 0], "points": points})
    text = "Regions: # Stored as JSON string\n" + json.dumps(regions) + "\n"
    t0 = time.process_time()
    topology = mod.parse_region_map(text, "pie.regions")
    seconds = time.process_time() - t0
    outcome = f"{sum(map(len, topology.adjacent.values())) // 2} adjacent pairs"
else:
    from ltl_stack.spec.english_files import parse_english
    from ltl_stack.spec.errors import SpecError
    sentences, members = size // 10000, size % 10000
    names = [f"r{i}" for i in range(members)]
    text = "Regions: " + ", ".join(names) + "\ngroup G is " + ", ".join(names) + "\n" + "visit all G\n" * sentences
    t0 = time.process_time()
    try:
        spec = parse_english(text, "v.spec")
        outcome = f"{len(spec.sys_liveness)} goals"
    except SpecError:
        outcome = "refused"
    seconds = time.process_time() - t0
print(json.dumps({"seconds": seconds, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "outcome": outcome, "input_bytes": len(text)}))
"""


def measure(kind: str, size: int, module_dir: str, repeats: int = 3, cap: float = 300) -> dict:
    runs = []
    for _ in range(repeats):
        try:
            done = subprocess.run([sys.executable, "-c", CHILD, kind, str(size), module_dir], capture_output=True,
                                  text=True, timeout=cap, cwd=ROOT)
        except subprocess.TimeoutExpired:
            return {"seconds": float("inf"), "peak_mb": float("nan"), "outcome": f"> {cap:g} s (killed)",
                    "input_bytes": 0}
        if done.returncode:
            raise RuntimeError(done.stderr[-2000:])
        runs.append(json.loads(done.stdout))
    best = dict(runs[0])
    best["seconds"] = statistics.median(r["seconds"] for r in runs)
    best["peak_mb"] = statistics.median(r["peak_mb"] for r in runs)
    return best


def main() -> None:
    quick = "--quick" in sys.argv
    old_dir = tempfile.mkdtemp(prefix="bench_hostile_")
    old = subprocess.run(["git", "show", f"{BASE}:src/ltl_stack/transfer/python2.py"], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    Path(old_dir, "python2_old.py").write_text(old)
    old = subprocess.run(["git", "show", f"{BASE}:src/ltl_stack/spec/region_map.py"], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    Path(old_dir, "region_map_old.py").write_text(old)
    rows = ["| item | size | input | old: CPU s | old: peak MB | new: CPU s | new: peak MB | new outcome |",
            "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for n in ((5000, 10000) if quick else (5000, 10000, 20000, 40000)):
        before = measure("print", n, old_dir, repeats=1 if n >= 20000 else 3)
        after = measure("print", n, "-")
        rows.append(f"| Python 2 print statements | {n:,} | {after['input_bytes'] / 1e3:.0f} KB | "
                    f"{before['seconds']:.2f} | {before['peak_mb']:.0f} | {after['seconds']:.3f} | "
                    f"{after['peak_mb']:.0f} | {after['outcome']} |")
    for n in ((500,) if quick else (500, 1000, 3000)):
        before = measure("pie", n, old_dir, repeats=1, cap=150)
        after = measure("pie", n, "-", repeats=1 if n >= 3000 else 3)
        rows.append(f"| LTLMoP pie map, thin slices | {n:,} | {after['input_bytes'] / 1e3:.0f} KB | "
                    f"{before['seconds']:.2f} | {before['peak_mb']:.0f} | {after['seconds']:.2f} | "
                    f"{after['peak_mb']:.0f} | {after['outcome']} |")
    for sentences, members in ((10, 500), (10, 1000), (100, 2000)):
        after = measure("visit", sentences * 10000 + members, "-")
        rows.append(f"| visit all G | {sentences} x {members:,} | {after['input_bytes'] / 1e3:.0f} KB | | | "
                    f"{after['seconds']:.2f} | {after['peak_mb']:.0f} | {after['outcome']} |")
    print("\n".join(rows))


if __name__ == "__main__":
    main()

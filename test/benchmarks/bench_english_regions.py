"""Structured English reader on many regions: clauses, formula nodes, time and memory.

Each size runs in a fresh process (peak RSS is per process). Two inputs per size: a ``Regions:``
declaration (every region touches every other) and a square grid ``.regions`` map (each cell
touches its four neighbours; adjacency from the geometry). With ``--pythonpath DIR`` the same is
measured for another checkout's code (the peer: the reader before its clauses became linear in the
regions), under an address-space
cap so that a quadratic reader stops instead of swapping.

    python test/benchmarks/bench_english_regions.py --sizes 600 3000
    python test/benchmarks/bench_english_regions.py --sizes 600 --pythonpath /tmp/old/src
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile

WORKER = r'''
import json, os, resource, sys, tempfile, time
from ltl_stack.spec.english_files import parse_english
from ltl_stack.spec.formula import children
kind, n = sys.argv[1], int(sys.argv[2])
folder = tempfile.mkdtemp()
if kind == "declared":
    text = "Sensors: s\nRegions: " + ", ".join(f"r{i}" for i in range(n)) + f"\nvisit r0\nvisit r{n - 1}\n"
else:
    w = int(n ** 0.5)
    h = (n + w - 1) // w
    cells = [{"name": "boundary", "type": "rect", "position": [0, 0], "size": [10 * w, 10 * h]}]
    cells += [{"name": f"r{i}", "type": "rect", "position": [10 * (i % w), 10 * (i // w)], "size": [10, 10]}
              for i in range(n)]
    with open(os.path.join(folder, "grid.regions"), "w") as f:
        f.write("Regions:\n" + json.dumps(cells) + "\n")
    text = f"Sensors: s\nMap: grid.regions\nvisit r0\nvisit r{n - 1}\n"
start = time.perf_counter()
spec = parse_english(text, os.path.join(folder, "task.spec"))
seconds = time.perf_counter() - start
sections = ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness")
seen, stack = set(), [c.formula for s in sections for c in spec.section(s)]
while stack:
    f = stack.pop()
    if id(f) not in seen:
        seen.add(id(f))
        stack.extend(children(f))
print(json.dumps({"bytes": len(text), "clauses": sum(len(spec.section(s)) for s in sections), "nodes": len(seen),
                  "seconds": seconds, "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
'''


def run(kind: str, n: int, pythonpath: str | None, cap_mb: int) -> dict:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath + os.pathsep + env.get("PYTHONPATH", "")

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (cap_mb * 2**20, cap_mb * 2**20))

    with tempfile.TemporaryDirectory() as folder:
        script = os.path.join(folder, "worker.py")
        with open(script, "w") as f:
            f.write(WORKER)
        done = subprocess.run([sys.executable, script, kind, str(n)], env=env, capture_output=True, text=True,
                              preexec_fn=limit, timeout=600)
    if done.returncode:
        return {"error": (done.stderr.strip().splitlines() or ["failed"])[-1]}
    return json.loads(done.stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[600, 3000])
    parser.add_argument("--pythonpath", help="measure another checkout's src folder")
    parser.add_argument("--cap-mb", type=int, default=3000, help="address-space cap of each worker (MB)")
    args = parser.parse_args()
    print("| input | regions | bytes | clauses | formula nodes | time (s) | peak RSS (MB) |")
    print("|---|---|---|---|---|---|---|")
    for kind in ("declared", "grid"):
        for n in args.sizes:
            r = run(kind, n, args.pythonpath, args.cap_mb)
            if "error" in r:
                print(f"| {kind} | {n} | | | | | stopped: {r['error']} |")
            else:
                print(f"| {kind} | {n} | {r['bytes']} | {r['clauses']} | {r['nodes']} | {r['seconds']:.2f} | "
                      f"{r['rss_mb']:.0f} |")


if __name__ == "__main__":
    main()

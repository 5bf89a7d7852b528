"""Hostile but valid input: time and peak memory of the spec and synthesis layers (run on demand).

    python test/benchmarks/bench_synthesis_hostile.py            # every case, a markdown table on stdout
    python test/benchmarks/bench_synthesis_hostile.py --case sum400

Each case runs in a fresh subprocess; its peak RSS is ``ru_maxrss`` of that child and "baseline" is the
same child's RSS after the imports, so "added" is what the work itself took. Cases:

- ``sum400``: ``synthesize`` of a structured clause summing 400 integers (``x0 + … + x399 = 5 -> y'``);
- ``parse8mb``: ``load_spec`` of an 8 MB .slugsin file (40,000 clauses of 200 bytes);
- ``english``/``infix``: rendering a 440-byte slugsin clause whose ``$`` buffer entries each use the
  previous one twice (2^30 nodes as a tree);
- ``explain``: ``synthesize --explain`` of an unrealizable spec with that clause;
- ``timeout``: ``synthesize --timeout 0.5`` of a spec that needs ~30 s (a 16-bit counter);
- ``memory``: ``synthesize --max-memory 16M`` of a random 3-CNF (exit 5 expected).
"""
from __future__ import annotations

import argparse
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SYNTHESIZE = ROOT / "scripts" / "synthesize"

PROBE = """
import resource, sys, time, warnings
warnings.filterwarnings("ignore")
from ltl_stack.spec import load_spec, clause_in_words, formula_to_infix
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
start = time.perf_counter()
kind, path = sys.argv[1], sys.argv[2]
spec = load_spec(path)
if kind == "english":
    out = clause_in_words(spec.sys_safety[0], "sys_safety")
elif kind == "infix":
    out = formula_to_infix(spec.sys_safety[0].formula)
else:
    out = ""
print(time.perf_counter() - start, base, len(out))
"""


def doubling_clause(levels: int) -> str:
    entries = ["| a' b"] + [f"^ ? {k} ! ? {k}" if k % 2 else f"& ? {k} | b ? {k}" for k in range(levels - 1)]
    return f"$ {levels} " + " ".join(entries)


def write_cases(folder: Path) -> dict[str, Path]:
    files = {}
    ints = "\n".join(f"x{k}:0...7" for k in range(400))
    files["sum400"] = folder / "sum400.structuredslugs"
    files["sum400"].write_text(f"[INPUT]\n{ints}\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n"
                               + " + ".join(f"x{k}" for k in range(400)) + " = 5 -> y'\n")
    rng = random.Random(1)
    names = [f"p{k}" for k in range(60)]
    clauses = []
    while sum(len(c) + 1 for c in clauses) < 8 * 2**20:
        words = []
        for _ in range(24):
            words += [rng.choice("&|^"), "!" if rng.random() < 0.3 else ""]
        tail = " ".join(rng.choice(names) + rng.choice(["", "'"]) for _ in range(25))
        clauses.append(" ".join(w for w in words if w) + " " + tail)
    files["parse8mb"] = folder / "big.slugsin"
    files["parse8mb"].write_text("[INPUT]\n" + "\n".join(names[:30]) + "\n[OUTPUT]\n" + "\n".join(names[30:])
                                 + "\n[SYS_TRANS]\n" + "\n".join(clauses) + "\n")
    shared = doubling_clause(30)
    files["shared"] = folder / "shared.slugsin"
    files["shared"].write_text(f"[INPUT]\na\nb\n\n[OUTPUT]\nc\n\n[SYS_TRANS]\n{shared}\n")
    files["explain"] = folder / "shared_unrealizable.slugsin"
    files["explain"].write_text(f"[INPUT]\na\nb\n\n[OUTPUT]\nc\n\n[SYS_TRANS]\n{shared}\n"
                                f"| {shared} c'\n! c'\n\n[SYS_LIVENESS]\nc\n")
    files["counter"] = folder / "counter.structuredslugs"
    files["counter"].write_text("[OUTPUT]\nx:0...65535\n\n[SYS_INIT]\nx = 0\n\n[SYS_TRANS]\nx' = x + 1 | x' = x\n\n"
                                "[SYS_LIVENESS]\nx = 65535\n")
    lines = ["[INPUT]", *[f"v{k}" for k in range(90)], "", "[OUTPUT]", "o", "", "[ENV_INIT]"]
    for _ in range(260):
        lines.append(" | ".join(("!" if rng.random() < 0.5 else "") + f"v{v}" for v in rng.sample(range(90), 3)))
    files["cnf"] = folder / "cnf.structuredslugs"
    files["cnf"].write_text("\n".join(lines) + "\n")
    return files


def run(argv: list[str], timeout: float = 900) -> dict:
    """Wall time, exit code and peak RSS (MB) of a child process."""
    wrapper = ("import resource, subprocess, sys, time; t = time.perf_counter(); "
               "r = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
               "print(r.returncode, time.perf_counter() - t, "
               "resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); print(r.stdout[-300:]); "
               "print(r.stderr[-300:])")
    out = subprocess.run([sys.executable, "-c", wrapper, *argv], capture_output=True, text=True, timeout=timeout)
    first, *rest = out.stdout.splitlines() or ["? ? ?"]
    code, seconds, rss = first.split()
    return {"code": int(code), "seconds": float(seconds), "rss_mb": int(rss) / 1024, "output": "\n".join(rest)}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--case", nargs="*", help="run only these cases")
    args = p.parse_args(argv)
    folder = Path(tempfile.mkdtemp(prefix="hostile_"))
    files = write_cases(folder)
    py = sys.executable
    cases = {
        "sum400": [py, str(SYNTHESIZE), str(files["sum400"]), "--quiet"],
        "parse8mb": [py, "-c", PROBE, "parse", str(files["parse8mb"])],
        "english": [py, "-c", PROBE, "english", str(files["shared"])],
        "infix": [py, "-c", PROBE, "infix", str(files["shared"])],
        "explain": [py, str(SYNTHESIZE), str(files["explain"]), "--explain", "--quiet"],
        "timeout": [py, str(SYNTHESIZE), str(files["counter"]), "--timeout", "0.5", "--quiet"],
        "memory": [py, str(SYNTHESIZE), str(files["cnf"]), "--max-memory", "16M", "--quiet"],
    }
    print("| case | input | exit | wall s | peak RSS MB | note |")
    print("|---|---|---|---|---|---|")
    for name, command in cases.items():
        if args.case and name not in args.case:
            continue
        source = {"sum400": "sum400", "parse8mb": "parse8mb", "english": "shared", "infix": "shared",
                  "explain": "explain", "timeout": "counter", "memory": "cnf"}[name]
        size = files[source].stat().st_size
        result = run(command)
        note = ""
        if name in ("parse8mb", "english", "infix"):
            seconds, base_kb, length = result["output"].split()[:3]
            added = result["rss_mb"] - int(base_kb) / 1024
            note = f"work {float(seconds):.2f} s, +{added:.0f} MB over the imports"
            if name == "parse8mb":
                note += f" ({added * 2**20 / size:.1f}x the file)"
            else:
                note += f", text {int(length)} chars"
        print(f"| {name} | {size:,} B | {result['code']} | {result['seconds']:.2f} | {result['rss_mb']:.0f} | {note} |",
              flush=True)
    time.sleep(0)
    return 0


if __name__ == "__main__":
    sys.exit(main())

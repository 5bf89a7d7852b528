"""Python 2 transfer of programs with many ``print`` statements (on demand): CPU time and peak
memory against the program's size, the reader before the change as the peer in the same run.

    python test/benchmarks/bench_python2_prints.py [--counts 10000,20000,40000] [--base COMMIT]

Each measurement is two fresh child processes reading the program with ``python2_parse_text`` (what
the transfer does with a Python 2 file before Python 3's ``ast``): CPU seconds in one, the peak of
the Python allocations (``tracemalloc``) in the other. Figures go to docs/BENCHMARKS.md.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tarfile
import tempfile
from io import BytesIO
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BASE = "d195746"  # main before the streaming reader

CHILD = r"""
import json, sys, time, tracemalloc
if sys.argv[2] != "-":
    sys.path.insert(0, sys.argv[2])
from ltl_stack.transfer.python2 import python2_parse_text
text = "import sys\n" + "".join(f"print 'line', {i}\n" for i in range(int(sys.argv[1])))
if sys.argv[3] == "trace":
    tracemalloc.start()
t0 = time.process_time()
python2_parse_text(text, "prints.py")
seconds = time.process_time() - t0
peak = tracemalloc.get_traced_memory()[1] if tracemalloc.is_tracing() else 0
print(json.dumps({"seconds": seconds, "peak": peak, "bytes": len(text)}))
"""


def measure(count: int, code: str) -> dict:
    runs = []
    for mode in ("time", "trace"):
        done = subprocess.run([sys.executable, "-c", CHILD, str(count), code, mode], capture_output=True, text=True,
                              cwd=ROOT, timeout=1800)
        if done.returncode:
            raise RuntimeError(done.stderr[-2000:])
        runs.append(json.loads(done.stdout))
    return {"seconds": runs[0]["seconds"], "peak": runs[1]["peak"], "bytes": runs[1]["bytes"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--counts", default="10000,20000,40000", help="print statements, comma-separated")
    parser.add_argument("--base", default=BASE, help="the commit whose reader is the peer")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="bench_python2_"))
    archive = subprocess.run(["git", "archive", args.base, "src"], capture_output=True, cwd=ROOT, check=True).stdout
    with tarfile.open(fileobj=BytesIO(archive)) as tar:
        tar.extractall(folder / "old")
    old = str(folder / "old" / "src")
    print("| prints | program | before: CPU s | before: peak | after: CPU s | after: peak |")
    print("| --- | --- | --- | --- | --- | --- |")
    for count in (int(c) for c in args.counts.split(",")):
        before, after = measure(count, old), measure(count, "-")
        size = after["bytes"]
        cells = [f"{r['seconds']:.2f} | {r['peak'] / 2**20:.0f} MB ({r['peak'] / size:.1f}x)" for r in (before, after)]
        print(f"| {count:,} | {size / 1e3:.0f} KB | {cells[0]} | {cells[1]} |", flush=True)


if __name__ == "__main__":
    main()

"""``load_spec`` of one long formula line (on demand): time and peak memory against the line's size,
the readers before the change as the peer in the same run.

    python test/benchmarks/bench_long_line.py [--sizes 1,2,4,8] [--base COMMIT]

Each measurement is two fresh child processes: CPU seconds of ``load_spec`` in one, the peak of the
Python allocations it made (``tracemalloc``, which slows it) in the other, as a multiple of the file's
size (the file's bytes and text are part of it). Shapes: ``chain``, a
right-nested ``& p & q …`` (how slugs writes a conjunction), and ``random``, a random prefix formula
over ``! & | ^``. The old code is ``src`` of ``BASE`` read from git into a temporary folder.
Figures go to docs/BENCHMARKS.md ("One long formula line").
"""
from __future__ import annotations

import random
import tempfile
from pathlib import Path

from old_code import arguments, cells, child_code, measure, old_src, table_head

BASE = "d195746"  # main before the readers' memory work
NAMES = [f"p{k}" for k in range(60)]

CHILD = child_code("from ltl_stack.spec import load_spec", "spec = load_spec(sys.argv[1])",
                   '{"clauses": len(spec.sys_safety)}')


def write_line(path: Path, shape: str, size: int) -> int:
    rng = random.Random(1)
    words: list[str] = []
    total = 0
    if shape == "chain":
        while total < size:
            words += ["&", rng.choice(NAMES)]
            total += 3 + len(words[-1])
        words.append("p0")
    else:
        need = 1
        while need:
            if total < size and (need == 1 or rng.random() < 0.5):
                op = rng.choice("!&|^")
                need += 0 if op == "!" else 1
                words.append(op)
            else:
                words.append(rng.choice(NAMES) + rng.choice(["", "'"]))
                need -= 1
            total += len(words[-1]) + 1
    path.write_text("[INPUT]\n" + "\n".join(NAMES[:30]) + "\n[OUTPUT]\n" + "\n".join(NAMES[30:])
                    + "\n[SYS_TRANS]\n" + " ".join(words) + "\n")
    return path.stat().st_size


def main() -> None:
    args = arguments(__doc__, BASE, "--sizes", "1,2,4,8", "line sizes in MiB, comma-separated")
    old = old_src(args.base, "bench_long_line_")
    folder = Path(tempfile.mkdtemp(prefix="bench_long_line_"))
    table_head("shape", "file")
    for shape in ("chain", "random"):
        for mib in (float(s) for s in args.sizes.split(",")):
            path = folder / f"{shape}.slugsin"
            size = write_line(path, shape, int(mib * 2**20))
            before, after = measure(CHILD, str(path), old), measure(CHILD, str(path), "-")
            print(f"| {shape} | {size / 2**20:.1f} MB | {cells(before, after, size, 1)} |", flush=True)


if __name__ == "__main__":
    main()

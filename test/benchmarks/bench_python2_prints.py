"""Python 2 transfer of programs with many ``print`` statements (on demand): CPU time and peak
memory against the program's size, the reader before the change as the peer in the same run.

    python test/benchmarks/bench_python2_prints.py [--counts 10000,20000,40000] [--base COMMIT]

Each measurement is two fresh child processes reading the program with ``python2_parse_text`` (what
the transfer does with a Python 2 file before Python 3's ``ast``): CPU seconds in one, the peak of
the Python allocations (``tracemalloc``) in the other. Figures go to docs/BENCHMARKS.md.
"""
from __future__ import annotations

from old_code import arguments, cells, child_code, measure, old_src, table_head

BASE = "d195746"  # main before the streaming reader

SETUP = """from ltl_stack.transfer.python2 import python2_parse_text
text = "import sys\\n" + "".join(f"print 'line', {i}\\n" for i in range(int(sys.argv[1])))"""
CHILD = child_code(SETUP, 'python2_parse_text(text, "prints.py")', '{"bytes": len(text)}')


def main() -> None:
    args = arguments(__doc__, BASE, "--counts", "10000,20000,40000", "print statements, comma-separated")
    old = old_src(args.base, "bench_python2_")
    table_head("prints", "program")
    for count in (int(c) for c in args.counts.split(",")):
        before, after = measure(CHILD, str(count), old), measure(CHILD, str(count), "-")
        size = after["bytes"]
        print(f"| {count:,} | {size / 1e3:.0f} KB | {cells(before, after, size, 2)} |", flush=True)


if __name__ == "__main__":
    main()

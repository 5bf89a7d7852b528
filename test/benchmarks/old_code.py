"""What the benchmarks that take the code before a change as their peer share: that code read from git,
and one measurement as two fresh child processes (CPU seconds in one, the peak of the Python allocations
in the other, since ``tracemalloc`` slows what it traces).

A child is ``child_code(setup, work, fields)``, run as ``python -c CODE ARGUMENT SRC MODE``: ``SRC`` is
the ``src`` folder to import ``ltl_stack`` from (``-``: the installed one), ``MODE`` is ``time`` or
``trace``; ``setup`` reads ``ARGUMENT`` (``sys.argv[1]``) and is not measured, ``work`` is.
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


def arguments(doc: str, base: str, option: str, default: str, meaning: str) -> argparse.Namespace:
    """The command line: ``option`` (the sizes to measure) and ``--base`` (the commit of the peer)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument(option, default=default, help=meaning)
    parser.add_argument("--base", default=base, help="the commit whose code is the peer")
    return parser.parse_args()


def table_head(*columns: str) -> None:
    """The head of the Markdown table: ``columns``, then CPU and peak before and after."""
    names = [*columns, "before: CPU s", "before: peak", "after: CPU s", "after: peak"]
    print("| " + " | ".join(names) + " |")
    print("|" + " --- |" * len(names))


def cells(before: dict, after: dict, size: int, digits: int) -> str:
    """CPU seconds and the peak (MB, and as a multiple of ``size`` bytes) before and after, as table cells."""
    return " | ".join(f"{r['seconds']:.{digits}f} | {r['peak'] / 2**20:.0f} MB ({r['peak'] / size:.1f}x)"
                      for r in (before, after))


def old_src(base: str, prefix: str) -> str:
    """The ``src`` folder of commit ``base``, extracted from git into a new temporary folder."""
    folder = Path(tempfile.mkdtemp(prefix=prefix))
    archive = subprocess.run(["git", "archive", base, "src"], capture_output=True, cwd=ROOT, check=True).stdout
    with tarfile.open(fileobj=BytesIO(archive)) as tar:
        tar.extractall(folder / "old")
    return str(folder / "old" / "src")


def child_code(setup: str, work: str, fields: str = "{}") -> str:
    """A child's program: ``setup``, then ``work`` timed (or traced); it prints one JSON line with
    ``seconds``, ``peak`` and the dict expression ``fields``."""
    return "\n".join([
        "import json, sys, time, tracemalloc",
        'if sys.argv[2] != "-":',
        "    sys.path.insert(0, sys.argv[2])",
        setup,
        'if sys.argv[3] == "trace":',
        "    tracemalloc.start()",
        "t0 = time.process_time()",
        work,
        "seconds = time.process_time() - t0",
        "peak = tracemalloc.get_traced_memory()[1] if tracemalloc.is_tracing() else 0",
        f'print(json.dumps({{"seconds": seconds, "peak": peak, **{fields}}}))',
    ])


def measure(child: str, argument: str, src: str) -> dict:
    """CPU seconds of a plain run of ``child`` and the peak of a traced one, with the traced run's
    other fields."""
    runs = []
    for mode in ("time", "trace"):
        done = subprocess.run([sys.executable, "-c", child, argument, src, mode], capture_output=True, text=True,
                              cwd=ROOT, timeout=1800)
        if done.returncode:
            raise RuntimeError(done.stderr[-2000:])
        runs.append(json.loads(done.stdout))
    return {**runs[1], "seconds": runs[0]["seconds"]}

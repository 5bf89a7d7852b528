"""Bounded memory under a violation flood, by counting what is kept, never RSS or time.

``test/benchmarks/bench_flood.py --trace`` found what still grew after the history was bounded: the
EC sets' literals (every disjunct held new ``Var``/``Not`` objects for every input) and, most of it,
freed BDD-manager tables glibc kept in the heap once it had raised its mmap threshold.
"""
from __future__ import annotations

import itertools
import os
import subprocess
import sys

from ltl_stack.runtime.resilience.characterize import Characterizer, Observation
from ltl_stack.spec import parse_structured
from ltl_stack.spec.formula import And, Not, Or

INPUTS = ["a", "b", "c", "d", "e"]
TEXT = ("[INPUT]\n" + "\n".join(INPUTS) + "\n\n[OUTPUT]\nx\n\n[ENV_INIT]\n!a\n\n[ENV_TRANS]\n!a'\n\n"
        "[SYS_TRANS]\nb' -> x'\n")


def formula_objects(roots) -> set[int]:
    """The distinct formula objects (by identity) reachable from ``roots``."""
    seen: set[int] = set()
    todo = list(roots)
    while todo:
        f = todo.pop()
        if id(f) in seen:
            continue
        seen.add(id(f))
        if isinstance(f, Not):
            todo.append(f.arg)
        elif isinstance(f, (And, Or)):
            todo.extend(f.args)
    return seen


def test_ec_disjuncts_share_their_literals():
    """Each disjunct keeps one conjunction; the literals exist once per (input, primed, value):
    3 objects each at most (a Var, a Not and the Var inside it). The old Characterizer made 1-2 new
    objects per input for every disjunct (here 1,056 objects for 96 disjuncts instead of <= 126)."""
    ch = Characterizer(parse_structured(TEXT, "flood.structuredslugs"))
    valuations = [dict(zip(INPUTS, bits)) for bits in itertools.product([False, True], repeat=5)]
    for k, (now, incoming) in enumerate(zip(valuations, valuations[7:] + valuations[:7] * 9)):
        ch.record(Observation(k, 0.0, now, {"x": False}, incoming))
        ch.record(Observation(k, 0.0, incoming, {"x": False}, now))
    disjuncts = ch.ec1 + ch.ec2
    assert len(ch.ec1) == 32 and len(ch.ec2) == 64, (len(ch.ec1), len(ch.ec2))
    kept = formula_objects(d.formula for d in disjuncts)
    assert len(kept) <= len(disjuncts) + 3 * 2 * len(INPUTS), len(kept)


MALLOC = """
import ctypes, sys
class Info(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                                               "fsmblks", "uordblks", "fordblks", "keepcost")]
libc = ctypes.CDLL(None)
if not hasattr(libc, "mallinfo2"):
    print("no glibc mallinfo2"); sys.exit(0)
libc.mallinfo2.restype = Info
libc.malloc.restype = ctypes.c_void_p
libc.free.argtypes = [ctypes.c_void_p]
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience
from ltl_stack.spec import parse_structured
BackgroundResilience(parse_structured(sys.argv[1], "flood.structuredslugs"), lock=None)
libc.free(libc.malloc(8 << 20))  # a replaced manager's tables are freed
before = libc.mallinfo2().hblks
block = libc.malloc(1 << 20)  # a table of the next manager
during = libc.mallinfo2().hblks
libc.free(block)
print(before, during, libc.mallinfo2().hblks)
"""


def test_freed_manager_tables_go_back_to_the_system():
    """Once a resilient strategy exists, a MiB block is an mmapped block (counted by glibc's
    ``mallinfo2``: one more while it lives, none once freed), also after a larger one was freed.
    On the old code glibc had raised its threshold to 8 MiB then: the block came from the heap
    (no mmapped block), and freed it stayed in the process."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    done = subprocess.run([sys.executable, "-c", MALLOC, TEXT], capture_output=True, text=True, env=env,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    if done.stdout.startswith("no glibc"):
        return  # nothing to count where there is no glibc (the setting is glibc's too)
    before, during, after = map(int, done.stdout.split())
    assert (during, after) == (before + 1, before), done.stdout

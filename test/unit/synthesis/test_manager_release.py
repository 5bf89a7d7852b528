"""A BDD manager freed in a reference cycle with its nodes: dd refuses to free a manager that still
has nodes ("Still N nodes referenced upon shutdown", an ignored exception printed as a traceback in a
node's log, and CUDD's memory left behind). Managers from ``new_manager`` outlive their last node.
Each case runs in a fresh interpreter, which prints what it cannot raise on its stderr."""
from __future__ import annotations

import subprocess
import sys

from helpers import needs_cudd

CYCLE = """
import gc, sys
from dd import cudd
from ltl_stack.synthesis import game
make = game.new_manager if sys.argv[1] == "new_manager" else lambda _cap: cudd.BDD()
class Holder:
    pass
for _ in range(3):
    # the manager first, so that the collector may free it before the node
    manager = make(1 << 30)
    manager.declare("a")
    node = manager.var("a")
    holder = Holder()
    holder.manager, holder.node, holder.itself = manager, node, holder
    del manager, node, holder
    gc.collect()
print("held", len(game._MANAGERS))
"""


def run_cycle(make: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", CYCLE, make], capture_output=True, text=True, timeout=120)


@needs_cudd
def test_a_manager_in_a_cycle_with_its_nodes_is_freed_after_them():
    done = run_cycle("new_manager")
    assert done.returncode == 0, done.stderr
    assert "referenced upon shutdown" not in done.stderr, done.stderr
    assert done.stdout.split() == ["held", "0"], done.stdout  # released by the collection that freed the nodes


@needs_cudd
def test_without_it_dd_complains():
    """The same cycle with dd's manager as it is: the complaint this module prevents."""
    done = run_cycle("plain")
    assert "Still 1 nodes referenced upon shutdown" in done.stderr, done.stderr

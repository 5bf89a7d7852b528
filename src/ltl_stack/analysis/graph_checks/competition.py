"""Where output propositions compete (``conflicts.conflict_pairs``), once per run: shared by E2
(different outputs) and E3 (one output's several nodes)."""
from __future__ import annotations

from dataclasses import dataclass

from ltl_stack.analysis.conflicts import conflict_pairs
from ltl_stack.analysis.graph_checks.base import Context
from ltl_stack.analysis.result import Analysis


@dataclass(frozen=True)
class Competition:
    """On channel vertex ``vertex``: the competing pairs of different outputs (in spec order), each
    output's first node in such a pair, and per output its nodes that compete with each other."""

    vertex: int
    pairs: frozenset[tuple[str, str]]
    first: dict[str, str]
    same: dict[str, set[str]]


def competitions(a: Analysis, context: Context) -> list[Competition]:
    """The competitions of ``a``'s outputs per channel (computed once per ``context``)."""
    return context.once("competitions", lambda: _competitions(a, context))


def _competitions(a: Analysis, context: Context) -> list[Competition]:
    reaches = {(y, node): a.pub[(y, node)] for y in a.outputs for node in a.nodes.get(y, [])}
    rank = {y: i for i, y in enumerate(a.outputs)}
    found = []
    for v, pairs in conflict_pairs(a.graph, reaches, context.blocked, context.relays).items():
        first: dict[str, str] = {}  # output -> its first node in a competing pair
        prop_pairs = set()
        same: dict[str, set[str]] = {}
        for (y1, n1), (y2, n2) in pairs:
            if y1 == y2:
                same.setdefault(y1, set()).update((n1, n2))
                continue
            prop_pairs.add(tuple(sorted((y1, y2), key=rank.__getitem__)))
            for y, node in ((y1, n1), (y2, n2)):
                if y not in first or a.nodes[y].index(node) < a.nodes[y].index(first[y]):
                    first[y] = node
        found.append(Competition(v, frozenset(prop_pairs), first, same))
    return found


__all__ = ["Competition", "competitions"]

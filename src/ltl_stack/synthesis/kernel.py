"""The BDD kernel the fixpoint runs on: CUDD (``dd.cudd``, the default) or oxidd (Rust, from PyPI).

The fixpoints of ``fixpoint.solve`` need few operations, and those are one small interface, the
subset of ``dd``'s manager API that ``Game.cpre_sys``, ``Game.prime`` and ``relation.Relation``
call:

- ``true``, ``false``; on functions ``&``, ``|``, ``~``, ``==`` (structural equality: canonical)
- ``exist(names, u)``, ``forall(names, u)``, ``and_exists(u, v, names)``, ``or_forall(u, v, names)``
- ``let(renaming, u)`` with a mapping from variable names to variable functions (``prime``)
- ``support(u)`` (variable names), ``count(u, nvars)``

``dd.cudd.BDD`` is that interface (its fused operations live on the module; ``relation`` finds them
there). ``OxiddManager`` implements it on ``oxidd.bcdd`` (BDDs with complement edges, fused
``apply_exists``/``apply_forall``, a cached ``substitute``) with a *static* variable order: oxidd
does not sift, so it is given the order CUDD found while building the game and running the first
controllable predecessors (``fixpoint.solve``), where the same fixpoint is several times cheaper
than in the PyPI wheel's CUDD (compiled without optimisation, see docs/BENCHMARKS.md).

``OxiddGame`` is a ``Game`` whose BDDs live in an ``OxiddManager``: the same ``Game`` methods run on
it (``cpre_sys``, ``prime``, ``deadlock_free_sys_rel``), so the fixpoint code is the same for both
kernels. ``to_cudd`` copies its results (the winning region and the iterates the strategy needs)
back into the game's CUDD manager, where strategy extraction, explicit export, recovery and
explanation run whichever kernel solved.

oxidd has abi3 wheels for CPython >= 3.9 only; without it (Python 3.8, or not installed) every
game is solved in CUDD. ``LTL_STACK_KERNEL`` (``cudd``, ``oxidd``, ``auto``, the default) forces
the choice; ``choose`` documents the automatic one.
"""
from __future__ import annotations

import copy
import importlib.util
import os
from collections.abc import Iterable, Mapping

_OXIDD: list = []  # the imported (BCDDManager, BooleanOperator, DDMemoryError), once needed


def _oxidd() -> tuple:
    """oxidd's classes, imported on first use (``import oxidd`` costs ~0.1 s of start-up)."""
    if not _OXIDD:
        from oxidd.bcdd import BCDDManager
        from oxidd.protocols import BooleanOperator
        from oxidd.util import DDMemoryError

        _OXIDD.extend((BCDDManager, BooleanOperator, DDMemoryError))
    return tuple(_OXIDD)


#: environment variable that forces the kernel: "cudd", "oxidd" or "auto"
KERNEL_ENV = "LTL_STACK_KERNEL"
#: the kernel choices ("auto": oxidd when installed and the fixpoint outlasts the warm-up)
KINDS = ("auto", "cudd", "oxidd")
#: the automatic choice takes oxidd for games whose fixpoint needs at least this many controllable
#: predecessors in the warm-up (smaller fixpoints end in CUDD before the copy could pay)
WARMUP_CPRE = 48
#: bytes an oxidd inner node takes with its share of the unique table (to size the node table
#: from the memory cap: oxidd fails with its ``DDMemoryError`` past it, and ``solve`` falls back to CUDD)
NODE_BYTES = 32
#: share of the game's memory cap given to oxidd's nodes (CUDD keeps the game meanwhile)
SHARE = 0.5
#: apply-cache entries (allocated up front, unlike CUDD's growing cache: ~100 MB)
CACHE_ENTRIES = 1 << 22


def capacity(max_memory: int) -> tuple[int, int]:
    """(inner nodes, apply-cache entries) of the oxidd manager for a memory cap of ``max_memory`` bytes."""
    nodes = max(1 << 16, int(max_memory * SHARE) // NODE_BYTES)
    return nodes, min(CACHE_ENTRIES, max(1 << 12, nodes // 4))


def requested() -> str:
    """The kernel asked for by ``LTL_STACK_KERNEL`` ("auto" when unset or unknown)."""
    value = os.environ.get(KERNEL_ENV, "auto").strip().lower()
    return value if value in KINDS else "auto"


_AVAILABLE: list = []


def available() -> bool:
    """Whether oxidd is installed (found without importing it)."""
    if not _AVAILABLE:
        _AVAILABLE.append(importlib.util.find_spec("oxidd") is not None)
    return _AVAILABLE[0]


def is_memory_error(error: BaseException) -> bool:
    """Whether ``error`` is oxidd's "out of memory" (its node table reached ``capacity``)."""
    return bool(_OXIDD) and isinstance(error, _OXIDD[2])


def describe(kind: str | None = None) -> str:
    """The kernel choice in words, for the backend line tools print once."""
    kind = requested() if kind is None else kind
    if kind == "cudd" or not available():
        return "fixpoints in CUDD" + ("" if kind == "cudd" else " (oxidd not installed)")
    if kind == "oxidd":
        return "fixpoints in oxidd"
    return f"fixpoints in oxidd when they outlast {WARMUP_CPRE} controllable predecessors in CUDD"


class OxiddManager:
    """``dd``'s manager interface (the part the fixpoint uses) on an oxidd BCDD manager.

    Variables are named as in the CUDD manager and created in ``order`` (top first): oxidd keeps that
    order. ``max_memory`` bytes bound the node table (``capacity``; oxidd's ``DDMemoryError`` past it).
    """

    kernel = "oxidd"

    def __init__(self, order: list[str], max_memory: int) -> None:
        manager, self._op, _ = _oxidd()
        self._m = manager(*capacity(max_memory), 1)
        self._index = {name: i for i, name in zip(self._m.add_named_vars(order), order)}
        self._names = {i: name for name, i in self._index.items()}
        self.true = self._m.true()
        self.false = self._m.false()
        self._vars = {name: self._m.var(i) for name, i in self._index.items()}
        self._cubes: dict[tuple, object] = {}
        self._substitutions: dict[int, tuple] = {}

    def var(self, name: str):
        return self._vars[name]

    def _cube(self, names: Iterable[str]):
        key = tuple(names)
        cube = self._cubes.get(key)
        if cube is None:
            cube = self.true
            for name in key:
                cube &= self._vars[name]
            self._cubes[key] = cube
        return cube

    def exist(self, names: Iterable[str], u):
        return u.exists(self._cube(names))

    def forall(self, names: Iterable[str], u):
        return u.forall(self._cube(names))

    def and_exists(self, u, v, names: Iterable[str]):
        return u.apply_exists(self._op.AND, v, self._cube(names))

    def or_forall(self, u, v, names: Iterable[str]):
        return u.apply_forall(self._op.OR, v, self._cube(names))

    def let(self, renaming: Mapping[str, object], u):
        """``u`` with each variable named in ``renaming`` replaced by its function (a parallel
        substitution; the substitution object is kept per mapping, so oxidd caches across calls)."""
        entry = self._substitutions.get(id(renaming))
        if entry is None or entry[0] is not renaming:
            pairs = [(self._index[k], v) for k, v in renaming.items()]
            entry = self._substitutions[id(renaming)] = (renaming, u.make_substitution(pairs))
        return u.substitute(entry[1])

    def support(self, u) -> set:
        """Names of the variables ``u`` depends on."""
        seen: set = set()
        found: set = set()
        stack = [u]
        while stack:
            f = stack.pop()
            pair = f.cofactors()
            if pair is None:
                continue
            if f in seen:
                continue
            seen.add(f)
            found.add(self._names[f.node_var()])
            stack.extend(pair)
        return found

    def count(self, u, nvars: int) -> int:
        return u.sat_count(nvars)

    def __len__(self) -> int:
        return self._m.num_inner_nodes()


class Copier:
    """Copies BDDs between the game's CUDD manager and an ``OxiddManager`` (both in the same order),
    node by node with memoised shared nodes (iterative: deep BDDs do not hit the recursion limit)."""

    def __init__(self, cudd, ox: OxiddManager) -> None:
        self.cudd = cudd
        self.ox = ox
        self._to_ox: dict[int, object] = {}
        self._to_cudd: dict = {}

    def to_oxidd(self, u):
        """The oxidd function of CUDD function ``u``."""
        ox, memo, cudd_true = self.ox, self._to_ox, self.cudd.true
        stack = [u]
        while stack:
            f = stack[-1]
            r = ~f if f.negated else f
            key = int(r)
            if key in memo:
                stack.pop()
                continue
            if r == cudd_true:
                memo[key] = ox.true
                stack.pop()
                continue
            low, high = r.low, r.high
            kl, kh = int(~low if low.negated else low), int(~high if high.negated else high)
            if kl in memo and kh in memo:
                stack.pop()
                lo = ~memo[kl] if low.negated else memo[kl]
                hi = ~memo[kh] if high.negated else memo[kh]
                memo[key] = ox.var(r.var).ite(hi, lo)
            else:
                if kh not in memo:
                    stack.append(high)
                if kl not in memo:
                    stack.append(low)
        r = ~u if u.negated else u
        v = memo[int(r)]
        return ~v if u.negated else v

    def to_cudd(self, f):
        """The CUDD function of oxidd function ``f`` (CUDD's dynamic reordering must be off)."""
        cudd, memo, names = self.cudd, self._to_cudd, self.ox._names
        stack = [f]
        while stack:
            g = stack[-1]
            if g in memo:
                stack.pop()
                continue
            pair = g.cofactors()
            if pair is None:
                memo[g] = cudd.true if g == self.ox.true else cudd.false
                stack.pop()
                continue
            high, low = pair
            if high in memo and low in memo:
                stack.pop()
                memo[g] = cudd.ite(cudd.var(names[g.node_var()]), memo[high], memo[low])
            else:
                if high not in memo:
                    stack.append(high)
                if low not in memo:
                    stack.append(low)
        return memo[f]


def oxidd_game(game, max_memory: int):
    """``game`` (a built ``Game`` in CUDD) copied into a fresh ``OxiddManager`` in CUDD's current
    variable order: a ``Game`` object whose manager, sets and relations are oxidd's, and the
    ``Copier`` that brings results back."""
    from ltl_stack.synthesis.relation import Relation

    bdd = game.bdd
    levels = bdd.var_levels
    ox = OxiddManager(sorted(levels, key=levels.get), max_memory)
    copier = Copier(bdd, ox)
    view = copy.copy(game)
    for name in list(vars(view)):  # a method replaced on the instance would run on CUDD's BDDs
        if callable(getattr(type(game), name, None)):
            delattr(view, name)
    view.bdd = ox
    view.true, view.false = ox.true, ox.false
    view.may_reorder = False
    conv = copier.to_oxidd
    view.env_init, view.sys_init = conv(game.env_init), conv(game.sys_init)
    view.env_goals = [conv(u) for u in game.env_goals]
    view.sys_goals = [conv(u) for u in game.sys_goals]
    check = game.deadline.check
    view.env_rel = Relation(ox, [conv(u) for u in game.env_rel.parts], check=check)
    view.sys_rel = Relation(ox, [conv(u) for u in game.sys_rel.parts], check=check)
    view._next_bdds = {v: ox.var(w) for v, w in game._to_next.items()}
    view._current_bdds = {v: ox.var(w) for v, w in game._to_current.items()}
    view._variable_bdds = {}
    view._alive = None
    return view, copier

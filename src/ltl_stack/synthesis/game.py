"""The BDD encoding of a GR(1) specification: the game structure of thesis Def. 4.3.5.

A ``Game`` holds one BDD manager (``dd.cudd``; ``dd.autoref`` only when CUDD cannot be imported)
with two variables per proposition ``p``: the current-state variable named ``p`` and the
next-state variable named ``p'`` (``Game.prime_name``). By default they are declared interleaved
(``x0 x0' x1 x1' ... y0 y0' ...``, inputs first, in the spec's order) and each pair is grouped, so
dynamic reordering moves the two together and renaming between them stays cheap; when the safety
sections conjoin far smaller in the block order (all current, then all next variables, ungrouped)
the game is built in that order instead (``Game._conjoin``; ``Game.interleave`` says which).

Stable API (other modules, ``explain.py`` and the differential tests rely on it):

- ``bdd``                         the manager; ``true`` / ``false`` its constants
- ``inputs``, ``outputs``         proposition names (current-state variable names)
- ``inputs_next``, ``outputs_next``   the matching next-state variable names
- ``variables``, ``variables_next``   inputs then outputs, current / next
- ``prime(u)``, ``unprime(u)``    rename current -> next / next -> current
- ``env_init``, ``sys_init``      conjunctions of the init clauses (current variables only)
- ``env_rel``, ``sys_rel``        the safety sections as partitioned relations (``relation.Relation``:
                                  clusters with a quantification schedule); every part of the engine
                                  works on these
- ``env_trans``, ``sys_trans``    the same conjunctions as single BDDs, built on first use only (for
                                  callers outside the engine; ``Relation.built`` counts it)
- ``env_goals``, ``sys_goals``    one BDD per liveness clause; ``[true]`` when the section is empty
                                  (goals may mention next variables: they constrain transitions;
                                  ``liveness_has_next`` says whether any does)
- ``clauses(section)``            ``[(Clause, BDD)]`` per clause of any section of ``SECTIONS``
- ``violated(section, current, nxt)``  the clauses of ``section`` that a valuation breaks
- ``cpre_sys(target)``            positions from which the system can force the next transition
                                  into ``target`` (Eq. 4.2's controllable predecessor)
- ``cpre_env(target)``            positions from which the environment can force it (dual operator)
- ``deadlock_free_sys_rel()``     ``sys_rel`` restricted to moves after which the environment
                                  still has an admissible input (used by the cooperative strategy)
- ``alive()``                     positions with an admissible next input (``exists next. env_trans``)
- ``admissible(values)``          ``env_trans`` restricted to a valuation (stepping: false = violated)
- ``joint_rel(sys_rel)``          ``env_trans & sys_trans`` as one relation (cooperative analyses)
- ``keep_order()``                save the variable order sifting found (``order_cache``); a new
                                  ``Game`` of the same spec starts in it (``order_reused``)
- ``pre_exists(target)``          positions from which some joint move of both players satisfies
                                  ``target`` (existential predecessor; ``vacuity``)
- ``to_bdd(formula)``             any ``ltl_stack.spec.formula`` node to a BDD
- ``deadline``, ``max_memory``    the limits of the run (``ltl_stack.synthesis.options``): the memory
                                  cap is set on the manager before the first clause is built, and
                                  every loop over BDD operations calls ``deadline.check()``

Semantics follow slugs: the system moves after seeing the environment's next input, and wins if
the environment breaks its safety assumptions first, so
``cpre_sys(T) = forall inputs'. env_trans -> exists outputs'. sys_trans & T``.
"""
from __future__ import annotations

import gc
import operator
import sys
import threading
import warnings
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager

from ltl_stack.spec.formula import And, Const, Formula, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.model import SECTIONS, Clause, Spec
from ltl_stack.synthesis import kernel, order_cache
from ltl_stack.synthesis.build_progress import BuildProgress
from ltl_stack.synthesis.errors import MemoryLimitReached
from ltl_stack.synthesis.options import LOOSE_UP_TO, MANAGER_ESTIMATE, NO_DEADLINE, Deadline, memory_cap
from ltl_stack.synthesis.relation import Relation

# dd imports networkx for one thing only, its ``to_nx`` graph export, which ltl_stack never calls;
# importing networkx costs ~90 ms, as much as the rest of a ``synthesize`` run on a small spec.
# dd itself treats networkx as optional (``dd._utils`` catches the ImportError), so networkx is
# marked absent while dd is first imported (a ``None`` entry in ``sys.modules`` makes an import
# fail: documented Python behaviour) and the mark is taken out again right after: any later
# ``import networkx`` in the process works as usual. If a dd release ever needs networkx to import
# at all, the plain import is done instead (only the start-up cost comes back).
_HIDE_NETWORKX = "networkx" not in sys.modules and "dd" not in sys.modules
if _HIDE_NETWORKX:
    sys.modules["networkx"] = None  # type: ignore[assignment]
try:
    try:  # pragma: no cover - which branch runs depends on the installation
        from dd import cudd as _backend

        BACKEND = "cudd"
    except ImportError as _error:  # pragma: no cover
        if _HIDE_NETWORKX and _error.name == "networkx":
            del sys.modules["networkx"]
            for _name in [m for m in sys.modules if m == "dd" or m.startswith("dd.")]:
                del sys.modules[_name]
            _HIDE_NETWORKX = False
            from dd import cudd as _backend
        else:
            from dd import autoref as _backend
        BACKEND = "cudd" if _backend.__name__ == "dd.cudd" else "autoref"
finally:
    if _HIDE_NETWORKX and sys.modules.get("networkx", False) is None:
        del sys.modules["networkx"]


def backend_line() -> str:
    """Which BDD package synthesis runs on, in the words a tool prints once, with the fixpoint kernel
    (``kernel.describe``); without CUDD also where to read how to get it (dd has no CUDD wheel for
    Python 3.8; docs/python_versions.md)."""
    if BACKEND == "cudd":
        return f"BDDs: CUDD (dd.cudd), {kernel.describe()}"
    return ("BDDs: dd's pure-Python dd.autoref, as this dd has no CUDD: the same answers, slower; "
            "docs/python_versions.md says how to build dd with CUDD")


#: node count from which building the game and solving it use dynamic reordering
REORDER_THRESHOLD = 2_000

#: live nodes after game construction from which the fixpoint starts without dynamic reordering
#: (``fixpoint.solve``): construction has then sifted a big transition relation several times and
#: its order suits the fixpoint's sets, which stay within a few times its size, so more sifting
#: costs more than it saves (slugs' factory_assembly members with 16,000-80,000 nodes: 1.3-2.2x
#: faster without), while small games (moving_obstacle, cinderella: 1,000-5,000 nodes) grow
#: 10-500x in the fixpoint and need reordering from its start (2-25x slower without)
BIG_GAME = 10_000
#: ... until the live nodes pass this multiple of the game's nodes; then reordering is switched on
#: (a safety net for big games whose fixpoint does explode; switching later costs more, as one
#: sifting pass grows with the manager: at 8x factory_assembly_5x6_2_0 took > 200 s instead of 22 s)
BIG_GAME_GROWTH = 4

#: BDD variables (current and next) above which no dynamic reordering is done: one sifting pass
#: costs time in the square of the variables, and the specs that profit (slugs' families, the
#: thesis specs) have at most a few hundred; a sum over 400 integers (2,402 variables) took over
#: 10 minutes of sifting for a BDD of 7,000 nodes that builds in 0.2 s without it
REORDER_MAX_VARIABLES = 1_000

#: automatic variable order (see ``Game._conjoin``); measured on slugs' generated specs, where the
#: small factory_assembly members build 4-10x smaller safety BDDs in the block order while
#: cinderella (up to 4.2x), moving_obstacle, grid patrol and factory 5x5_2_0 do not stay 5x bigger
#: (a heuristic tuned on these few families: the margins are small)
RACE_START = 3_000
RACE_STOP = 4_000
RACE_RATIO = 5
RACE_CLAUSES = 2
#: clauses after its start within which the race must be won (factory_assembly members win within
#: 1-3; factory_assembly_7x3_1_0errors never does, and racing longer cost it 15 %)
RACE_WINDOW = 4
#: the race runs on the environment's safety section only: where the system's section was the one
#: 5-12x smaller in the block order (cinderella_stepmother_n5c3_12_by_9, moving_obstacle
#: 24x24_8glitches) the fixpoint was still 1.3-2.2x faster interleaved
RACE_SECTION = "env_safety"


class _BlockOrderWins(Exception):
    """Raised inside ``Game`` construction when the block variable order won the order race."""


#: Every CUDD manager made by ``new_manager`` that may still have nodes in use (see ``_release_managers``).
_MANAGERS: list = []
_MANAGERS_LOCK = threading.Lock()


def _release_managers(*_gc_info: object) -> None:
    """Let go of the managers nobody else holds and that hold no node any more.

    A game, its strategy and the nodes it made often sit in reference cycles (bound methods kept as
    attributes, exceptions kept with their frames). The collector then clears a node's reference to
    its manager before it frees the node, so the manager could be freed first: dd refuses that with
    "Still N nodes referenced upon shutdown" (printed as an ignored exception, a traceback in a node's
    log) and leaves CUDD's memory behind. Held here, a manager outlives its last node; this releases
    it after the collection that freed the nodes (a ``gc.callbacks`` hook) or at the next manager."""
    if (_gc_info and _gc_info[0] != "stop") or not _MANAGERS_LOCK.acquire(blocking=False):
        return  # (before a collection; or another thread is at it)
    try:
        kept = []
        while _MANAGERS:
            manager = _MANAGERS.pop()
            # references: ``manager`` here and getrefcount's argument (tested first: len() walks
            # CUDD's whole node table, and this runs after every collection)
            if sys.getrefcount(manager) <= 2 and len(manager) == 0:
                continue
            kept.append(manager)
        manager = None
        _MANAGERS.extend(kept)
    finally:
        _MANAGERS_LOCK.release()


def new_manager(max_memory: int):
    """A BDD manager whose memory cap is ``max_memory`` bytes from its first node on.

    CUDD starts with a small cache (it grows on demand) to start fast; past the cap an operation
    fails and ``memory_guard`` turns that into ``MemoryLimitReached``. The manager is kept alive
    until its last node is freed (``_release_managers``).
    """
    if BACKEND != "cudd":  # pragma: no cover
        return _backend.BDD()
    with memory_guard(max_memory):
        bdd = _backend.BDD(memory_estimate=min(max_memory, MANAGER_ESTIMATE), initial_cache_size=2**16)
        bdd.configure(max_memory=max_memory, loose_up_to=LOOSE_UP_TO)
    _release_managers()
    with _MANAGERS_LOCK:
        if _release_managers not in gc.callbacks:
            gc.callbacks.append(_release_managers)
        _MANAGERS.append(bdd)
    return bdd


@contextmanager
def memory_guard(max_memory: int | None) -> Iterator[None]:
    """Turn CUDD's failure at the memory cap (a NULL node, ``MemoryError``) into ``MemoryLimitReached``."""
    try:
        yield
    except (ValueError, RuntimeError, MemoryError) as e:
        if not isinstance(e, MemoryError) and "NULL" not in str(e) and "CUDD" not in str(e):
            raise
        cap = "its memory cap" if max_memory is None else f"the memory cap of {max_memory / 2**20:.0f} MiB"
        raise MemoryLimitReached(f"the BDDs outgrew {cap} (raise it with --max-memory)") from None


def prime_name(name: str) -> str:
    """The next-state variable name of proposition ``name``."""
    return name + "'"


class Game:
    """The BDD game of a ``Spec``. Build one per spec; all BDDs share ``self.bdd``."""

    def __init__(self, spec: Spec, *, bdd=None, interleave: bool | None = None,
                 fused: bool = True, max_memory: int | None = None, deadline: Deadline = NO_DEADLINE,
                 partition: bool = True, reuse_order: bool = True,
                 progress: Callable[[str], None] | None = None) -> None:
        """``interleave=None`` chooses the variable order (see ``_conjoin``): interleaved unless the
        safety conjunctions are much smaller with all current variables before all next ones.
        ``True``/``False`` force one order and ``fused=False`` quantifies after conjoining; those
        exist to measure the techniques. ``max_memory`` caps the manager (``options.memory_cap``;
        a manager passed as ``bdd`` keeps its own settings); ``deadline`` bounds the time of this
        and every later computation on the game. ``partition=False`` keeps each safety section as
        one BDD conjoined in file order (the monolithic engine, to measure partitioning and to test
        against). ``reuse_order`` starts a fresh manager in the order saved for this spec (or for
        one with the same propositions) by an earlier run (``order_cache``; see ``keep_order``).
        ``progress`` gets a line now and then while the BDDs are built (``build_progress``)."""
        self.partition = partition
        self.reuse_order = reuse_order and bdd is None
        #: "exact" (the saved order of this very spec: no sifting at all), "propositions" (one of a
        #: spec with the same propositions: a start, sifting stays on) or None
        self.order_reused: str | None = None
        self.max_memory = memory_cap(max_memory)
        self.deadline = deadline
        self._building: BuildProgress | None = None
        if progress is not None:
            self._building = BuildProgress(progress, sum(len(spec.section(name)) for name in SECTIONS))
        # the rival order of the race is sifted freely and built clause by clause; with thousands of
        # variables one clause such as x_i -> x_i' over all i is exponential in the block order
        race = (interleave is None and bdd is None and BACKEND == "cudd"
                and 2 * len(spec.inputs + spec.outputs) <= REORDER_MAX_VARIABLES)
        with memory_guard(self.max_memory):
            try:
                self._build(spec, bdd, interleave is not False, fused, race)
            except _BlockOrderWins:
                self._build(spec, None, False, fused, False)
        self._building = None

    def _setup(self, spec: Spec, bdd, interleave: bool) -> None:
        self.spec = spec
        self.interleave = interleave
        self.bdd = bdd if bdd is not None else new_manager(self.max_memory)
        self.inputs: list[str] = list(spec.inputs)
        self.outputs: list[str] = list(spec.outputs)
        self.inputs_next = [prime_name(v) for v in self.inputs]
        self.outputs_next = [prime_name(v) for v in self.outputs]
        self.variables = self.inputs + self.outputs
        self.variables_next = self.inputs_next + self.outputs_next
        #: dynamic reordering is allowed (few enough variables, see ``REORDER_MAX_VARIABLES``)
        self.may_reorder = BACKEND == "cudd" and 2 * len(self.variables) <= REORDER_MAX_VARIABLES
        saved = None
        if getattr(self, "reuse_order", False) and self.may_reorder and bdd is None:
            saved = order_cache.load(spec, set(self.variables) | set(self.variables_next))
            if saved is not None and saved[1]:
                self.may_reorder = False  # the order sifting ended with last time: keep it
        if BACKEND == "cudd" and not self.may_reorder:
            self.bdd.configure(reordering=False)
        self._declare()
        if saved is not None:
            try:
                _backend.reorder(self.bdd, {v: k for k, v in enumerate(saved[0])})
                self.order_reused = "exact" if saved[1] else "propositions"
            except Exception:  # pragma: no cover - a saved order is only a hint
                self.may_reorder = BACKEND == "cudd" and 2 * len(self.variables) <= REORDER_MAX_VARIABLES
        self._to_next = dict(zip(self.variables, self.variables_next))
        self._to_current = dict(zip(self.variables_next, self.variables))
        # the renamings as variable BDDs: ``let`` with names makes one BDD per variable on every
        # call (a few hundred calls per fixpoint), with BDDs it does the same substitution directly
        var = self.bdd.var
        self._next_bdds = {v: var(w) for v, w in self._to_next.items()}
        self._current_bdds = {v: var(w) for v, w in self._to_current.items()}
        self._variable_bdds: dict[tuple[str, bool], object] = {}  # (name, primed) -> its BDD, for to_bdd

    def _build(self, spec: Spec, bdd, interleave: bool, fused: bool, race: bool) -> None:
        self._setup(spec, bdd, interleave)
        self.fused = fused
        self._race = race
        self._alive = None
        self.true = self.bdd.true
        self.false = self.bdd.false

        self._clauses: dict[str, list[tuple[Clause, object]]] = {
            name: [self._clause_bdd(name, c) for c in spec.section(name)] for name in SECTIONS
        }
        self.env_init = self._conjoin("env_init")
        self.sys_init = self._conjoin("sys_init")
        #: rho_e and rho_s as partitioned relations (``relation.Relation``), scheduled for the
        #: quantification each one gets in ``cpre_sys``: rho_e over the next inputs, rho_s over the
        #: next outputs; ``env_trans``/``sys_trans`` are their single BDDs, built only on demand
        self.env_rel = self._relation("env_safety", self.inputs_next)
        self.sys_rel = self._relation("sys_safety", self.outputs_next)
        self.env_goals = [u for _, u in self._clauses["env_liveness"]] or [self.true]
        self.sys_goals = [u for _, u in self._clauses["sys_liveness"]] or [self.true]
        nxt = set(self.variables_next)
        #: True when some liveness formula mentions next-state variables (a transition goal)
        self.liveness_has_next = any(nxt & self.bdd.support(u) for u in self.env_goals + self.sys_goals)
        #: live BDD nodes once the game is built (the fixpoint's reordering policy starts from it)
        self.nodes = len(self.bdd)
        # slugs forbids primed outputs in env safety; if a spec has them, use the general cpre.
        self._env_sees_outputs_next = any(v in self.env_rel.support for v in self.outputs_next)

    def _clause_bdd(self, section: str, clause: Clause) -> tuple[Clause, object]:
        building = getattr(self, "_building", None)
        if building is not None:
            building.at(f"{section} line {clause.line}")
        u = self.to_bdd(clause.formula)
        if building is not None:
            building.clause_done()
        return clause, u

    def _check(self) -> None:
        """Between two BDD operations: the deadline, and the construction's progress."""
        self.deadline.check()
        building = getattr(self, "_building", None)
        if building is not None:
            building.tick()

    @property
    def env_trans(self):
        """rho_e as one BDD (built on first use from ``env_rel``; the engine's fixpoints, strategy,
        recovery and stepping use ``env_rel`` and never need it)."""
        return self.env_rel.conjunction()

    @property
    def sys_trans(self):
        """rho_s as one BDD (built on first use from ``sys_rel``)."""
        return self.sys_rel.conjunction()

    @property
    def env_sees_outputs_next(self) -> bool:
        """Whether the environment's safety mentions next outputs (slugs forbids it): then
        ``cpre_sys`` lets the system answer an input with an output that breaks that safety."""
        return self._env_sees_outputs_next

    # --- variables -------------------------------------------------------------------------
    def _declare(self) -> None:
        if self.interleave:
            names = []
            for v in self.variables:
                names += [v, prime_name(v)]
        else:
            names = self.variables + [prime_name(v) for v in self.variables]
        existing = set(self.bdd.vars)
        if BACKEND == "cudd" and not existing and names:
            # the last index first: CUDD then sizes its tables once instead of growing them every
            # few variables (each growth copies all of them: quadratic in thousands of variables)
            self.bdd.add_var(names[-1], index=len(names) - 1)
            for index, name in enumerate(names[:-1]):
                self.bdd.add_var(name, index=index)
        else:
            self.bdd.declare(*[n for n in names if n not in existing])
        # groups only matter to reordering, and each costs time linear in the groups before it
        if BACKEND == "cudd" and not existing and self.interleave and self.may_reorder:
            try:
                self.bdd.group({v: 2 for v in self.variables})
            except Exception:  # pragma: no cover - grouping is an optimisation only
                pass

    def prime(self, u):
        """Rename current-state variables of ``u`` to next-state ones (``u`` must not mention next)."""
        return self.bdd.let(self._next_bdds, u) if self._next_bdds else u

    def unprime(self, u):
        """Rename next-state variables of ``u`` to current-state ones (``u`` must not mention current)."""
        return self.bdd.let(self._current_bdds, u) if self._current_bdds else u

    # --- formulas ---------------------------------------------------------------------------
    def to_bdd(self, formula: Formula):
        """The BDD of a formula (iterative: slugsin formulas can nest thousands deep).

        Each node is visited twice (children first, then itself), shared subformulas once; time
        is linear in the formula's nodes plus the BDD operations (``deadline`` checked before each).
        """
        bdd = self.bdd
        check = self._check
        variables = self._variable_bdds
        done: dict[int, object] = {}
        stack: list[Formula] = [formula]
        while stack:
            node = stack[-1]
            key = id(node)
            if key in done:
                stack.pop()
                continue
            kind = type(node)
            if kind is Var:
                stack.pop()
                u = variables.get((node.name, node.primed))
                if u is None:
                    if node.name not in self._to_next:
                        raise KeyError(f"unknown proposition {node.name!r} (not an input or output)")
                    u = variables[(node.name, node.primed)] = bdd.var(
                        prime_name(node.name) if node.primed else node.name)
                done[key] = u
                continue
            if kind is Const:
                stack.pop()
                done[key] = bdd.true if node.value else bdd.false
                continue
            if kind is Not:
                kids: tuple = (node.arg,)
            elif kind is And or kind is Or:
                kids = node.args
            elif kind in _BINARY:
                kids = (node.left, node.right)
            else:
                raise TypeError(f"not a formula node: {node!r}")
            waiting = [k for k in kids if id(k) not in done]
            if waiting:
                stack.extend(waiting)
                continue
            stack.pop()
            check()
            if kind is Not:
                done[key] = ~done[id(kids[0])]
            elif kind is And:
                done[key] = _balanced([done[id(k)] for k in kids], bdd.true, operator.and_)
            elif kind is Or:
                done[key] = _balanced([done[id(k)] for k in kids], bdd.false, operator.or_)
            else:
                left, right = done[id(kids[0])], done[id(kids[1])]
                if kind is Xor:
                    done[key] = bdd.ite(left, ~right, right)
                elif kind is Implies:
                    done[key] = ~left | right
                else:
                    done[key] = bdd.ite(left, right, ~right)
        return done[id(formula)]

    def _conjoin(self, section: str):
        """Conjunction of a section's clauses in spec order, with dynamic reordering once the
        intermediate result is big (a smallest-first order was tried: slower on slugs' factory specs).

        Order race (``self._race``, env safety only, see ``RACE_SECTION``): once the conjunction
        passes ``RACE_START`` nodes, the same clauses are also conjoined in a scratch manager with
        the block order (all current variables, then all next ones, ungrouped, so CUDD's default
        sifting may move any variable).
        If the interleaved conjunction stays above ``RACE_START`` and ``RACE_RATIO`` times bigger
        for ``RACE_CLAUSES`` clauses in a row, ``_BlockOrderWins`` makes ``__init__`` rebuild the
        game in the block order; the race is given up (interleaving kept) once the block
        conjunction itself passes ``RACE_STOP`` nodes or ``RACE_WINDOW`` clauses went by.
        """
        acc = self.bdd.true
        reordering = False
        rival = rival_acc = None
        streak = 0
        clauses = self._clauses[section]
        if getattr(self, "_building", None) is not None:
            self._building.at(f"conjoining {section}")
        for k, (_, u) in enumerate(clauses):
            self._check()
            acc &= u
            if self._race and section == RACE_SECTION and rival is None and len(acc) > RACE_START:
                rival = Game.__new__(Game)
                rival.max_memory, rival.deadline = self.max_memory, self.deadline
                rival._setup(self.spec, None, False)
                rival_acc = rival.bdd.true
                started = k
                for clause, _ in clauses[:k]:
                    rival_acc &= rival.to_bdd(clause.formula)
            if rival is not None:
                rival_acc &= rival.to_bdd(clauses[k][0].formula)
                big = len(acc) > max(RACE_START, RACE_RATIO * len(rival_acc))
                streak = streak + 1 if big else 0
                if streak >= RACE_CLAUSES:
                    raise _BlockOrderWins
                if len(rival_acc) > RACE_STOP or k - started >= RACE_WINDOW:
                    self._race = False
                    rival = rival_acc = None
            if self.may_reorder and not reordering and len(acc) > REORDER_THRESHOLD // 2:
                self.bdd.configure(reordering=True)
                reordering = True
        if reordering:
            self.bdd.configure(reordering=False)
        return acc

    def _relation(self, section: str, quantified: list[str]) -> Relation:
        """A safety section as a ``Relation``: clusters of scheduled clauses (see ``relation.py``),
        built with dynamic reordering once a cluster grows past half ``REORDER_THRESHOLD``, as
        ``_conjoin`` does. With ``partition`` off (to measure it): one cluster, the file order."""
        clauses = [u for _, u in self._clauses[section]]
        if not self.partition:
            return Relation(self.bdd, [self._conjoin(section)], check=self.deadline.check)
        if getattr(self, "_building", None) is not None:
            self._building.at(f"clustering {section}")
        reordering = []

        def grown(nodes: int) -> None:
            if self.may_reorder and not reordering and nodes > REORDER_THRESHOLD // 2:
                self.bdd.configure(reordering=True)
                reordering.append(True)

        try:
            shrink = (lambda: _backend.reorder(self.bdd)) if self.may_reorder else None
            return Relation.from_clauses(self.bdd, clauses, quantified, check=self._check,
                                         grown=grown, shrink=shrink)
        finally:
            if reordering:
                self.bdd.configure(reordering=False)

    def keep_order(self) -> None:
        """Save the manager's variable order for the next ``Game`` of this spec (``order_cache``),
        when sifting has changed it (an order reused exactly is already saved)."""
        if BACKEND != "cudd" or not self.reuse_order or self.order_reused == "exact":
            return
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # dd warns about a unit change of another statistic
            if not self.bdd.statistics()["n_reorderings"]:
                return
        levels = self.bdd.var_levels
        order_cache.save(self.spec, sorted(levels, key=levels.get))

    def clauses(self, section: str) -> list[tuple[Clause, object]]:
        """``(Clause, BDD)`` for each clause of ``section`` (one of ``SECTIONS``)."""
        if section not in self._clauses:
            raise ValueError(f"unknown section {section!r}; expected one of {', '.join(SECTIONS)}")
        return list(self._clauses[section])

    def assignment(self, current: Mapping[str, bool], nxt: Mapping[str, bool] | None = None) -> dict:
        """A ``let``-assignment of current (and next) variables from proposition valuations."""
        values = {k: bool(v) for k, v in current.items()}
        for k, v in (nxt or {}).items():
            values[prime_name(k)] = bool(v)
        return values

    def cube(self, current: Mapping[str, bool], nxt: Mapping[str, bool] | None = None):
        """The BDD of a (partial) valuation of current and next variables."""
        return self.bdd.cube(self.assignment(current, nxt))

    def violated(self, section: str, current: Mapping[str, bool],
                 nxt: Mapping[str, bool] | None = None) -> list[Clause]:
        """The clauses of ``section`` that are false for the given (complete) valuation."""
        values = self.assignment(current, nxt)
        bad = []
        for clause, u in self._clauses[section]:
            if self.bdd.let(values, u) == self.bdd.false:
                bad.append(clause)
        return bad

    # --- predecessor operators ----------------------------------------------------------------
    def cpre_sys(self, target, sys_rel: Relation | None = None):
        """Positions where, for every admissible next input, some next output satisfies
        ``sys_trans & target`` (``target`` over current and next variables).

        ``sys_rel`` defaults to the spec's; the cooperative game passes a restricted one. Both
        quantifications go cluster by cluster (``Relation.exist_and`` over the next outputs, then
        ``Relation.forall_implies`` over the next inputs): ``env_trans`` is never built here.
        """
        trans = self.sys_rel if sys_rel is None else sys_rel
        bdd = self.bdd
        if self._env_sees_outputs_next:
            u = bdd.exist(self.outputs_next, ~self.env_trans | trans.conjoin(target))
            return bdd.forall(self.inputs_next, u)
        if not self.fused:
            moves = bdd.exist(self.outputs_next, trans.conjoin(target))
            return bdd.forall(self.inputs_next, ~self.env_trans | moves)
        moves = trans.exist_and(target, self.outputs_next)
        return self.env_rel.forall_implies(moves, self.inputs_next)

    def cpre_env(self, target):
        """Positions from which the environment can force ``target``: some admissible next input
        such that every next output allowed by ``sys_trans`` satisfies ``target``."""
        forced = self.sys_rel.forall_implies(target, self.outputs_next)
        return self.env_rel.exist_and(forced, self.inputs_next)

    def alive(self):
        """Positions with an admissible next input (``exists next. env_trans``; computed once)."""
        if self._alive is None:
            self._alive = self.env_rel.exist_and(self.true, self.variables_next)
        return self._alive

    def joint_rel(self, sys_rel: Relation | None = None) -> Relation:
        """``env_trans & sys_trans`` (``sys_rel`` if given) as one relation: both players' clusters."""
        trans = self.sys_rel if sys_rel is None else sys_rel
        return Relation(self.bdd, self.env_rel.parts + trans.parts, check=self.deadline.check)

    def set_safety(self, section: str, clauses: list) -> None:
        """Replace rho_e (``section="env_safety"``) or rho_s (``"sys_safety"``) by the conjunction of
        ``clauses`` (BDDs of this manager): the sub-game variants of ``explain`` use it on copies."""
        if section == "env_safety":
            self.env_rel = Relation.from_clauses(self.bdd, clauses, self.inputs_next, check=self.deadline.check)
            self._alive = None
            self._env_sees_outputs_next = any(v in self.env_rel.support for v in self.outputs_next)
        elif section == "sys_safety":
            self.sys_rel = Relation.from_clauses(self.bdd, clauses, self.outputs_next, check=self.deadline.check)
        else:
            raise ValueError(f"not a safety section: {section!r}")

    def deadlock_free_sys_rel(self) -> Relation:
        """``sys_rel`` restricted to next positions that still have an admissible next input."""
        return self.sys_rel.with_part(self.prime(self.alive()))

    def pre_exists(self, target, sys_rel: Relation | None = None):
        """Positions with some admissible next input and some next output allowed by ``sys_rel``
        such that the transition satisfies ``target`` (over current and next variables): the
        existential predecessor of both players moving together (``vacuity``'s fair states).

        ``sys_rel`` defaults to the spec's; ``Relation(bdd, [])`` gives the environment's moves
        alone. The outputs are quantified cluster by cluster with the system's relation first, then
        the inputs with the environment's, as ``cpre_sys`` does; ``env_trans`` is not built here.
        """
        trans = self.sys_rel if sys_rel is None else sys_rel
        bdd = self.bdd
        if self._env_sees_outputs_next:
            return bdd.exist(self.variables_next, self.env_trans & trans.conjoin(target))
        if not self.fused:
            moves = bdd.exist(self.outputs_next, trans.conjoin(target))
            return bdd.exist(self.inputs_next, self.env_trans & moves)
        moves = trans.exist_and(target, self.outputs_next)
        return self.env_rel.exist_and(moves, self.inputs_next)

    def admissible(self, values: Mapping[str, bool]):
        """``env_trans`` restricted to a valuation (current variables, maybe next inputs): false
        when the inputs break rho_e, else a BDD over what ``values`` leaves open."""
        return self.env_rel.restrict(values)

    # --- counting ----------------------------------------------------------------------------
    def count(self, u, *, next_too: bool = False) -> int:
        """Number of valuations of ``u`` over the current (and optionally next) variables."""
        nvars = len(self.variables) * (2 if next_too else 1)
        return int(self.bdd.count(u, nvars=nvars))


#: operands from which an n-ary conjunction or disjunction is combined as a balanced tree
BALANCED_FROM = 8


def _balanced(vals: list, unit, combine):
    """``vals[0] op vals[1] op ...`` as a balanced tree of pairs when there are many operands.

    One long left-to-right chain costs time in the square of its length when the operands sit one
    below the other in the variable order (each step copies the whole accumulated BDD above the new
    operand: 4,000 clauses ``x_i -> x_i'`` took seconds); pairing neighbours first makes that linear
    times log, and a few operands keep the chain.
    """
    if len(vals) < BALANCED_FROM:
        acc = unit
        for v in vals:
            acc = combine(acc, v)
        return acc
    while len(vals) > 1:
        paired = [combine(vals[i], vals[i + 1]) for i in range(0, len(vals) - 1, 2)]
        if len(vals) % 2:
            paired.append(vals[-1])
        vals = paired
    return vals[0] if vals else unit


#: formula nodes with ``left`` and ``right`` operands
_BINARY = (Xor, Implies, Iff)

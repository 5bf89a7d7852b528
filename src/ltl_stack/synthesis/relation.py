"""A transition relation kept as a conjunction of small clusters, with a quantification schedule.

The safety section of a GR(1) spec (rho_e or rho_s of thesis Def. 4.3.5) is a conjunction of
clauses. Conjoining them all into one BDD can make it large (tens of thousands of nodes on slugs'
factory_assembly family), and every controllable predecessor then quantifies over that whole BDD.
Here the clauses are instead grouped into clusters of at most ``CLUSTER_NODES`` nodes, and a
quantification over the relation is done cluster by cluster, each next-state variable quantified
right after the last cluster that mentions it (early quantification, as in image computation for
model checking: Burch, Clarke and Long, "Symbolic model checking with partitioned transition
relations", 1991; Ranjan et al., IWLS 1995):

    exists Q. (P_1 & ... & P_n & T)        = exists Q_n. (P_n & ... exists Q_1. (P_1 & exists Q_0. T))
    forall Q. (!(P_1 & ... & P_n) | T)     = forall Q_n. (!P_n | ... forall Q_1. (!P_1 | forall Q_0. T))

where Q_k are the variables of Q that P_k mentions and no later cluster does (Q_0: those no
cluster mentions). Both identities hold because a quantifier over a variable moves across a
conjunct or disjunct that does not mention it.

The order of the clusters (the *schedule*) is chosen from variable occupancy, not from the file:
the quantified variables are taken in increasing order of the number of clauses that mention them,
and each one's clauses are placed as soon as it is taken, so the variables that few clauses share
are quantified first and the intermediate BDDs carry as few live quantified variables as possible
(a bucket elimination order). Clauses that mention no quantified variable come first.

``Relation`` is the only representation of the safety sections in the engine: the fixpoints
(``Game.cpre_sys``, ``Game.cpre_env``), strategy extraction, recovery, explanation and stepping all
use its operations; ``conjunction()`` builds the single BDD on demand for callers that need it, and
counts how often it did (``built``) so that tests can show the fixpoint never does.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

#: nodes up to which consecutive clauses (in the schedule's order) are conjoined into one cluster
#: (a few thousand nodes: each quantification step is then cheap, and the number of steps small)
CLUSTER_NODES = 2_000
#: nodes up to which a relation whose clauses conjoin in file order stays one BDD: one quantification
#: over a BDD this small costs less than several over clusters and their intermediate results
#: (slugs' cinderella and moving_obstacle members: rho_s of ~2,200 nodes was 1.3x slower in two
#: clusters), while the relations that partitioning pays on are ten times bigger (factory_assembly's
#: rho_e: 18,000-74,000 nodes)
WHOLE_NODES = 2 * CLUSTER_NODES


def schedule(supports: Sequence[set], quantified: Iterable[str]) -> list[int]:
    """The order of clauses (indices into ``supports``) for early quantification of ``quantified``.

    Quantified variables are taken by increasing occupancy (clauses that mention them; ties by
    name, so the order does not depend on the file's), and each variable's clauses not yet placed
    are placed when it is taken. Clauses that mention no quantified variable come first, in their
    original order. Linear in the total occupancy.
    """
    quantified = set(quantified)
    occupants: dict[str, list[int]] = {}
    free = []
    for k, support in enumerate(supports):
        mentioned = support & quantified
        if not mentioned:
            free.append(k)
        for v in mentioned:
            occupants.setdefault(v, []).append(k)
    order = list(free)
    placed = set(free)
    for v in sorted(occupants, key=lambda v: (len(occupants[v]), v)):
        for k in occupants[v]:
            if k not in placed:
                placed.add(k)
                order.append(k)
    return order


class Relation:
    """A conjunction of BDD clusters over one manager, with quantification schedules.

    Built by ``Relation.from_clauses`` (clusters of the scheduled clauses) or ``Relation(bdd,
    parts)`` (the parts taken as they are, in that order). ``with_part`` gives the relation with one
    more conjunct (the cooperative game's restriction of rho_s).
    """

    def __init__(self, bdd, parts: Sequence, *, check=None) -> None:
        self.bdd = bdd
        self.parts = [u for u in parts if u != bdd.true]
        if any(u == bdd.false for u in self.parts):
            self.parts = [bdd.false]
        self._supports = [frozenset(bdd.support(u)) for u in self.parts]
        self.support = frozenset().union(*self._supports)
        self._check = check or (lambda: None)
        self._plans: dict[frozenset, tuple] = {}
        self._conjunction = None
        #: how often ``conjunction()`` built the single BDD (0 or 1: it is kept once built)
        self.built = 0

    @classmethod
    def from_clauses(cls, bdd, clauses: Sequence, quantified: Iterable[str], *, check=None,
                     limit: int | None = None, grown=None, shrink=None) -> Relation:
        """The conjunction of ``clauses`` (BDDs), scheduled for quantifying ``quantified`` (see
        ``schedule``) and clustered up to ``limit`` (default ``CLUSTER_NODES``) nodes per cluster;
        when the conjunction in the file's order never passes ``WHOLE_NODES`` (``limit`` when given)
        it is the one cluster. ``grown(nodes)``, when given,
        sees the size of each intermediate cluster (``Game`` switches reordering on with it);
        ``shrink()``, when given, is called once when the file-order conjunction first passes
        ``WHOLE_NODES`` (``Game`` sifts then: basicEvasion's rho_e is 385 nodes sifted, > 4,000 not)."""
        check = check or (lambda: None)
        whole_limit = WHOLE_NODES if limit is None else limit
        limit = CLUSTER_NODES if limit is None else limit
        clauses = [u for u in clauses if u != bdd.true]
        whole = bdd.true  # a relation that stays small in the file's order is kept as one BDD
        for u in clauses:
            check()
            whole &= u
            size = len(whole)
            if grown is not None:
                grown(size)
            if size > whole_limit and shrink is not None:
                shrink()  # once: sifting may make the whole relation small again
                shrink = None
                size = len(whole)
            if size > whole_limit:
                break
        else:
            return cls(bdd, [whole], check=check)
        order = schedule([set(bdd.support(u)) for u in clauses], quantified)
        parts: list = []
        acc = None
        for k in order:
            check()
            u = clauses[k]
            if acc is None:
                acc = u
                continue
            joined = acc & u
            size = len(joined)
            if grown is not None:
                grown(size)
            if size <= limit:
                acc = joined
            else:
                parts.append(acc)
                acc = u
        if acc is not None:
            parts.append(acc)
        return cls(bdd, _merged(parts, limit, check), check=check)

    def with_part(self, u) -> Relation:
        """This relation and ``u`` (appended last in the schedule)."""
        return Relation(self.bdd, self.parts + [u], check=self._check)

    def nodes(self) -> int:
        """Nodes of all clusters together (shared nodes counted once)."""
        if not self.parts:
            return 1
        return sum(len(u) for u in self.parts)

    # --- quantification ---------------------------------------------------------------------
    def _plan(self, qvars: frozenset) -> tuple:
        """(Q_0, [Q_1, ..., Q_n]) for the clusters in order (see the module docstring)."""
        plan = self._plans.get(qvars)
        if plan is None:
            later: set = set()
            steps = []
            for support in reversed(self._supports):
                steps.append(sorted((support & qvars) - later))
                later |= support
            steps.reverse()
            plan = self._plans[qvars] = (sorted(qvars - later), steps)
        return plan

    def exist_and(self, target, qvars: Iterable[str]):
        """``exists qvars. (relation & target)``, quantifying each variable as early as it can."""
        bdd = self.bdd
        first, steps = self._plan(frozenset(qvars))
        acc = bdd.exist(first, target) if first else target
        for k, part in enumerate(self.parts):
            self._check()
            acc = _and_exists(bdd, part, acc, steps[k])
        return acc

    def forall_implies(self, target, qvars: Iterable[str]):
        """``forall qvars. (relation -> target)``, quantifying each variable as early as it can."""
        bdd = self.bdd
        first, steps = self._plan(frozenset(qvars))
        acc = bdd.forall(first, target) if first else target
        for k, part in enumerate(self.parts):
            self._check()
            acc = _or_forall(bdd, ~part, acc, steps[k])
        return acc

    def conjoin(self, u):
        """``relation & u`` as one BDD (``u`` first: usually the smaller operand)."""
        acc = u
        for part in self.parts:
            self._check()
            acc &= part
        return acc

    # --- evaluation --------------------------------------------------------------------------
    def restrict(self, values: Mapping[str, bool]):
        """The relation with ``values`` substituted, as one BDD (its clusters restricted first)."""
        bdd = self.bdd
        acc = bdd.true
        for part in self.parts:
            acc &= bdd.let(values, part) if values else part
            if acc == bdd.false:
                break
        return acc

    def holds(self, values: Mapping[str, bool]) -> bool:
        """Whether a valuation of every variable the relation mentions satisfies it."""
        return self.restrict(values) == self.bdd.true

    def conjunction(self):
        """The whole relation as one BDD (built on first call and kept; ``built`` counts it)."""
        if self._conjunction is None:
            self.built += 1
            self._conjunction = self.conjoin(self.bdd.true)
        return self._conjunction


def _merged(parts: list, limit: int, check) -> list:
    """``parts`` with neighbours conjoined while the result stays within ``limit`` nodes.

    Clauses conjoined in the schedule's order can pass through BDDs far bigger than their
    conjunction (basicEvasion's rho_e: clusters of 994 and 91 nodes that conjoin to 385), so the
    clusters are offered to their neighbours once more: fewer steps for every quantification.
    """
    merged = parts[:1]
    for u in parts[1:]:
        check()
        joined = merged[-1] & u
        if len(joined) <= limit:
            merged[-1] = joined
        else:
            merged.append(u)
    return merged


def _and_exists(bdd, u, v, qvars: list):
    """``exists qvars. u & v`` fused when the backend can (dd.cudd), in two steps otherwise."""
    if not qvars:
        return u & v
    fused = getattr(bdd, "and_exists", None) or getattr(_module(bdd), "and_exists", None)
    if fused is not None:
        return fused(u, v, qvars)
    return bdd.exist(qvars, u & v)


def _or_forall(bdd, u, v, qvars: list):
    """``forall qvars. u | v`` fused when the backend can (dd.cudd), in two steps otherwise."""
    if not qvars:
        return u | v
    fused = getattr(bdd, "or_forall", None) or getattr(_module(bdd), "or_forall", None)
    if fused is not None:
        return fused(u, v, qvars)
    return bdd.forall(qvars, u | v)


_MODULES: dict = {}


def _module(bdd):
    """The ``dd`` module of a manager (``dd.cudd`` has the fused operations)."""
    kind = type(bdd)
    if kind not in _MODULES:
        import importlib

        _MODULES[kind] = importlib.import_module(kind.__module__)
    return _MODULES[kind]

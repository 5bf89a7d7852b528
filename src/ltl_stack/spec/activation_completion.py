"""The robotics conventions a Structured English spec gets for free (thesis section 4.3, [75]).

Regions and durative actions follow the activation–completion paradigm: the robot *activates*
``R`` ("head for region R") or ``a`` ("start action a"); the environment reports the *completion*
``R_rc`` ("the robot is in R") or ``a_ac`` ("a has finished"). The clauses below say how the
environment may answer and what the robot may ask for:

regions (``Reg`` and ``Reg^c``)
    env: the robot is in exactly one region (initially and always); heading for the region it is
    in, it stays; heading for a neighbour, it is next either where it was or there; heading
    nowhere, it stays where it is. Fairness: it eventually arrives where it keeps heading (or
    heads nowhere, or changes its mind).
    sys: at most one region is activated (initially and always); only the region the robot is
    in or a neighbour of it (the topology of the map).
durative actions (``Act`` and ``Act^c``)
    env: not finished initially; a finished action stays finished while it stays active; a
    completion appears only while the action is active (it resets when the activation falls, as
    ltl_stack's ``action_proposition`` node does). Fairness: an action kept active eventually
    finishes (or is withdrawn).

These are the clauses of ``config/clean_and_patrol/clean_and_patrol.structuredslugs``, generated
instead of written by hand. Every clause names the declaration it comes from.
"""
from __future__ import annotations

from collections.abc import Sequence

from ltl_stack.spec.formula import And, Formula, Iff, Implies, Not, Or, Var
from ltl_stack.spec.model import Clause
from ltl_stack.spec.region_map import RegionTopology

ACTION_COMPLETION = "_ac"
REGION_COMPLETION = "_rc"


#: from this many regions on, the generated clauses use the linear encodings below (smaller maps
#: keep the thesis' expanded forms, which read as the thesis prints them)
LINEAR_FROM = 16


def exactly_one(names: Sequence[str], primed: bool) -> Formula:
    """One of ``names`` is true and the others false."""
    lits = [Var(n, primed) for n in names]
    if len(lits) == 1:
        return lits[0]
    if len(lits) >= LINEAR_FROM:
        seen, at_most = _ladder(lits)
        return And((seen, at_most))
    return Or(tuple(And(tuple(v if j == i else Not(v) for j, v in enumerate(lits))) for i in range(len(lits))))


def at_most_one(names: Sequence[str], primed: bool) -> Formula:
    """The thesis' expanded form (Fig. 3.7): "only y_i" for each i, or none of them."""
    lits = [Var(n, primed) for n in names]
    if len(lits) >= LINEAR_FROM:
        return _ladder(lits)[1]
    terms = [And(tuple(v if j == i else Not(v) for j, v in enumerate(lits))) for i in range(len(lits))]
    terms.append(And(tuple(Not(v) for v in lits)))
    return Or(tuple(terms))


def _ladder(lits: list[Var]) -> tuple[Formula, Formula]:
    """(some literal is true, at most one is) in size linear in ``lits``: ``seen_i`` = "one of the
    first i is true" is a shared node built on ``seen_(i-1)``, and at most one holds when no literal
    is true after one before it was (the sequential encoding, without auxiliary variables)."""
    seen: Formula = lits[0]
    clashes = []
    for v in lits[1:]:
        clashes.append(Not(And((seen, v))))
        seen = Or((seen, v))
    return seen, And(tuple(clashes))


def none_of(names: Sequence[str], primed: bool) -> Formula:
    lits = tuple(Not(Var(n, primed)) for n in names)
    return lits[0] if len(lits) == 1 else And(lits)


def region_clauses(topology: RegionTopology, file: str, line: int, origin: str) -> dict[str, list[Clause]]:
    """Mutual exclusion, topology and arrival fairness of the regions of ``topology``."""
    regions = topology.regions
    rc = {r: r + REGION_COMPLETION for r in regions}
    out: dict[str, list[Clause]] = {"env_init": [], "env_safety": [], "env_liveness": [], "sys_init": [],
                                    "sys_safety": []}

    def add(section: str, formula: Formula, why: str) -> None:
        out[section].append(Clause(formula, f"({origin}) {why}", file, line))

    if not regions:
        return out
    completions = [rc[r] for r in regions]
    add("env_init", exactly_one(completions, False), "the robot starts in exactly one region")
    add("env_safety", exactly_one(completions, True), "the robot is in exactly one region")
    for r in regions:
        add("env_safety", Implies(And((Var(rc[r]), Var(r))), Var(rc[r], True)),
            f"heading for {r} while in {r}, the robot stays in {r}")
    linear = len(regions) >= LINEAR_FROM
    if linear:
        # one clause per region, O(min(neighbours, others)) each: with at most one region activated
        # (the robot's guarantee below) "heading for a neighbour s, next in r or s" for every s is
        # "heading for some neighbour, next in r or where it heads"
        index = {s: i for i, s in enumerate(regions)}
        any_active = Or(tuple(Var(s) for s in regions))
        arrived = Or(tuple(And((Var(s), Var(rc[s], True))) for s in regions))
        for r in regions:
            if topology.degree(r) == 0:
                continue
            if 2 * topology.degree(r) <= len(regions):
                near = _near(topology, r, index)
                heading = Or(tuple(Var(s) for s in near))
                target = Or(tuple(And((Var(s), Var(rc[s], True))) for s in near))
            else:
                others = _others(topology, r)
                heading = And((any_active, Not(Var(r)), *(Not(Var(s)) for s in others)))
                target = arrived
            add("env_safety", Implies(And((Var(rc[r]), heading)), Or((Var(rc[r], True), target))),
                f"heading from {r} for a neighbour of it, the robot is next in {r} or there")
    else:
        for r in regions:
            for s in regions:
                if s in topology.neighbours(r):
                    add("env_safety", Implies(And((Var(rc[r]), Var(s))), Or((Var(rc[r], True), Var(rc[s], True)))),
                        f"heading from {r} for its neighbour {s}, the robot is next in {r} or {s}")
    add("env_safety", Implies(none_of(regions, False), And(tuple(Iff(Var(rc[r]), Var(rc[r], True)) for r in regions))
                              if len(regions) > 1 else Iff(Var(rc[regions[0]]), Var(rc[regions[0]], True))),
        "heading for no region, the robot stays where it is")
    arrive = [And((Var(r), Var(rc[r], True))) for r in regions]
    change = [And((Var(r), Not(Var(r, True)))) for r in regions]
    add("env_liveness", Or((*arrive, none_of(regions, False), *change)),
        "the robot eventually reaches the region it keeps heading for")
    if len(regions) > 1:
        add("sys_init", at_most_one(regions, False), "the robot heads for at most one region")
        add("sys_safety", at_most_one(regions, True), "the robot heads for at most one region")
    nowhere = none_of(regions, True)  # one shared node
    index = {s: i for i, s in enumerate(regions)}
    for r in regions:
        if topology.degree(r) == len(regions) - 1:
            continue  # every region is a neighbour
        if linear and 2 * topology.degree(r) <= len(regions):
            # with "at most one region" above, the same as "none of the others"
            near = [Var(r, True), *(Var(s, True) for s in _near(topology, r, index)), nowhere]
            add("sys_safety", Implies(Var(rc[r], True), Or(tuple(near))),
                f"from {r} the robot heads only for {r} or a neighbour of it")
        else:
            add("sys_safety", Implies(Var(rc[r], True), none_of(_others(topology, r), True)),
                f"from {r} the robot heads only for {r} or a neighbour of it")
    return out


def _near(topology: RegionTopology, r: str, index: dict[str, int]) -> list[str]:
    """The regions ``r`` touches, in map order (clauses come out the same on every run)."""
    return sorted(topology.neighbours(r), key=index.__getitem__)


def _others(topology: RegionTopology, r: str) -> list[str]:
    """The regions ``r`` does not touch (itself excluded), in map order."""
    if topology.degree(r) == len(topology.regions) - 1:
        return []
    near = topology.neighbours(r)
    return [s for s in topology.regions if s != r and s not in near]


def place_clauses(topology: RegionTopology, file: str, line: int, origin: str) -> dict[str, list[Clause]]:
    """LTLMoP's region model (``createTopologyFragment``, ``createInitialRegionFragment``): a region
    is a robot proposition saying where the robot is; it is in exactly one region, initially and
    always, and moves in one step only to a neighbour (or stays)."""
    regions = topology.regions
    out: dict[str, list[Clause]] = {"sys_init": [], "sys_safety": []}
    if not regions:
        return out

    def add(section: str, formula: Formula, why: str) -> None:
        out[section].append(Clause(formula, f"({origin}) {why}", file, line))

    add("sys_init", exactly_one(regions, False), "the robot starts in exactly one region")
    add("sys_safety", exactly_one(regions, True), "the robot is in exactly one region")
    index = {s: i for i, s in enumerate(regions)}
    for r in regions:
        if topology.degree(r) == len(regions) - 1:
            continue  # it may go anywhere
        moves = [Var(r, True), *(Var(s, True) for s in _near(topology, r, index))]
        add("sys_safety", Implies(Var(r), moves[0] if len(moves) == 1 else Or(tuple(moves))),
            f"from {r} the robot moves only to a neighbour of it (or stays)")
    return out


def action_clauses(actions: Sequence[str], file: str, line: int, origin: str) -> dict[str, list[Clause]]:
    """Completion of the durative ``actions``: how ``a_ac`` follows ``a`` (environment assumptions)."""
    out: dict[str, list[Clause]] = {"env_init": [], "env_safety": [], "env_liveness": []}

    def add(section: str, formula: Formula, why: str) -> None:
        out[section].append(Clause(formula, f"({origin}) {why}", file, line))

    for a in actions:
        ac = a + ACTION_COMPLETION
        add("env_init", Not(Var(ac)), f"{a} has not finished at the start")
        add("env_safety", Implies(And((Var(ac), Var(a))), Var(ac, True)), f"finished {a} stays finished while {a} is active")
        add("env_safety", Implies(Not(Var(a)), Not(Var(ac, True))), f"{a} finishes only while it is active")
        add("env_liveness", Or((And((Var(a), Var(ac, True))), Not(Var(a)), And((Var(a), Not(Var(a, True)))))),
            f"{a}, kept active, eventually finishes")
    return out

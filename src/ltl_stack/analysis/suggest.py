"""Specification additions suggested by the graph analysis (thesis section 3.5.2.3).

For output propositions that reach the same topic or action (E2), the controller must never make
two of them true at once: "at most one of y1 ... yk is true". The thesis writes it as the
disjunction of "exactly yi" terms and "none" (Fig. 3.7, 3.8):

    always ((y1 and not y2 ...) or (not y1 and y2 ...) or ... or (not y1 and not y2 ...))

Semantics chosen: the constraint goes into ``[SYS_TRANS]`` over next-state (primed) values, which
covers every state after the first, *and* into ``[SYS_INIT]`` over current values, so the initial
state cannot start two conflicting nodes either. Without the ``[SYS_INIT]`` part a controller could
legally begin in a state that has, say, ``stop`` and ``topLane`` both true.

When making outputs exclusive breaks realizability (thesis Example 9), the inputs that drive those
outputs are the usual culprit; ``input_exclusion_for`` proposes the matching environment
assumption (``[ENV_TRANS]`` primed, ``[ENV_INIT]`` unprimed).
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

from ltl_stack.analysis.conflicts import maximal_cliques
from ltl_stack.spec.formula import And, Formula, Not, Or, Var, variables
from ltl_stack.spec.formula_text import formula_in_words
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.synthesis.game import Game

SYSTEM = "system"
ENVIRONMENT = "environment"


@dataclass(frozen=True)
class MutualExclusion:
    """At most one of ``propositions`` is true at any time; ``topics`` say why (the shared channels)."""

    propositions: tuple[str, ...]
    topics: tuple[str, ...] = ()
    side: str = SYSTEM  # SYSTEM: outputs (a guarantee); ENVIRONMENT: inputs (an assumption)
    in_spec: bool = False  # the spec already guarantees it (``mark_guaranteed``)

    def formula(self, primed: bool) -> Formula:
        """The thesis' expanded form: one "only y_i" term per proposition, plus "none of them"."""
        lits = [Var(p, primed) for p in self.propositions]
        terms = [And(tuple(v if j == i else Not(v) for j, v in enumerate(lits))) for i in range(len(lits))]
        terms.append(And(tuple(Not(v) for v in lits)))
        return Or(tuple(terms))

    @property
    def sections(self) -> tuple[str, str]:
        """(safety section, init section) the constraint is added to."""
        return ("sys_safety", "sys_init") if self.side == SYSTEM else ("env_safety", "env_init")

    def sentence(self) -> str:
        """``a, b and c are mutually exclusive`` (Structured English, short form)."""
        names = [formula_in_words(Var(p)) for p in self.propositions]  # quotes names like 'not'
        listed = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
        return f"{listed} are mutually exclusive"

    def clauses(self, file: str = "<graph analysis>") -> dict[str, Clause]:
        """Section name -> the clause to add there."""
        why = f" (they share {', '.join(self.topics)})" if self.topics else ""
        text = self.sentence() + why
        safety, init = self.sections
        return {safety: Clause(self.formula(True), text, file, 0), init: Clause(self.formula(False), text, file, 0)}

    def to_dict(self) -> dict:
        return {"propositions": list(self.propositions), "topics": list(self.topics), "side": self.side,
                "already_in_spec": self.in_spec}


def mutual_exclusions(groups: Iterable[tuple[str, Sequence[str] | Iterable[tuple[str, str]]]],
                      order: Sequence[str] = ()) -> list[MutualExclusion]:
    """One suggestion per distinct set of conflicting propositions, from per-channel groups.

    A group is (channel, propositions that all compete there) or (channel, competing pairs); pairs
    are turned into the maximal sets in which every two compete, so that two propositions merged
    by a mux are never made exclusive. Groups with the same set are merged (their channels listed
    together); a set contained in a larger suggested set is dropped, since the larger exclusion
    already implies it.
    """
    rank = {p: i for i, p in enumerate(order)}
    by_set: dict[frozenset[str], list[str]] = {}
    for channel, members in groups:
        members = list(members)
        sets = maximal_cliques(members) if members and isinstance(members[0], tuple) else [frozenset(members)]
        for props in sets:
            if len(props) >= 2:
                by_set.setdefault(props, []).append(channel)
    kept = [s for s in by_set if not any(s < other for other in by_set)]
    result = []
    for s in kept:
        props = tuple(sorted(s, key=lambda p: (rank.get(p, len(rank)), p)))
        covered = sorted({c for other, chans in by_set.items() if other <= s for c in chans})
        result.append(MutualExclusion(props, tuple(covered)))
    result.sort(key=lambda m: (-len(m.propositions), m.propositions))
    return result


def mark_guaranteed(spec: Spec, suggestions: Sequence[MutualExclusion]) -> list[MutualExclusion]:
    """``suggestions`` with ``in_spec`` set on those the spec already guarantees: every transition its
    safety clauses allow, and every initial state its init clauses allow, keeps the exclusion
    (a sufficient check, on BDDs). Adding such a suggestion changes nothing; the report says so."""
    if not suggestions:
        return list(suggestions)
    game = Game(spec)
    allowed_start = game.env_init & game.sys_init
    marked = []
    for s in suggestions:
        kept = game.env_rel.conjoin(game.sys_rel.conjoin(~game.to_bdd(s.formula(True)))) == game.false and \
            (allowed_start & ~game.to_bdd(s.formula(False))) == game.false
        marked.append(replace(s, in_spec=kept))
    return marked


def add_to_spec(spec: Spec, suggestions: Iterable[MutualExclusion], file: str = "<graph analysis>") -> Spec:
    """A copy of ``spec`` with every suggestion's clauses appended to their sections."""
    for s in suggestions:
        for section, clause in s.clauses(file).items():
            spec = spec.with_section(section, [*spec.section(section), clause])
    return spec


def input_exclusion_for(spec: Spec, outputs: Iterable[str]) -> MutualExclusion | None:
    """The assumption "the inputs that drive ``outputs`` are mutually exclusive", or None.

    Driving inputs: inputs that occur in a system safety clause together with one of ``outputs``
    (``if you are sensing left_arrow then do move_left``). This is what thesis Example 9 needed.
    """
    wanted = set(outputs)
    inputs = set(spec.inputs)
    found: set[str] = set()
    for clause in spec.sys_safety:
        names = {v.name for v in variables(clause.formula)}
        if names & wanted:
            found |= names & inputs
    if len(found) < 2:
        return None
    ordered = tuple(p for p in spec.inputs if p in found)
    return MutualExclusion(ordered, (), ENVIRONMENT)

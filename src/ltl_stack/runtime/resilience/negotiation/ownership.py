"""Who can keep a received assumption (thesis §4.8, Alg. 4 line 5; activation-completion §4.3).

Alg. 4 line 5 conjoins every assumption the peer sends with the receiver's system safety. A clause
that mentions a next-state output of the receiver is kept by its next move, as the thesis says. A
clause over the receiver's *sensors* only is decided by the environment's move; it is kept one of
two ways:

* **through the activations** its completion sensors report (``road_c'`` -> ``road'``), but only
  when that rewrite *implies* the literal clause: by induction over the receiver's environment
  safety (``implied_by_rewrite``) — if the literal clause L and its rewrite R hold now, every
  environment move the receiver assumes keeps L; and both hold at the current position. Then a
  strategy that keeps R keeps L at every step (D promising "never in the kitchen" promises never to
  head there, and its own assumption says it arrives only where it heads);
* otherwise **literally**, as the guarantee the peer sent: the receiver keeps it only where its
  moves leave the environment no way to break it (its env safety links its outputs to its sensors).
  When no strategy can do that, phi^nego is unrealizable and Alg. 4 goes on as the thesis says
  (4.8.2 or 4.8.3): a clause over sensors the receiver does not control (a global sensor, a third
  robot's proposition) is never turned into an assumption and reported as an adoption.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from ltl_stack.spec import formula_to_infix
from ltl_stack.spec.formula import Formula, Var, evaluate, variables
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.ops import map_vars
from ltl_stack.synthesis.game import Game

#: name endings of completion sensors (activation-completion, thesis §4.3): ``R_c`` / ``R_rc`` / ``a_ac``
#: report that the robot's own output ``R`` / ``a`` took effect
COMPLETION_SUFFIXES = ("_rc", "_ac", "_c")


def action_of(sensor: str, outputs: list[str]) -> str | None:
    """The receiver's output whose completion ``sensor`` reports (``road_c`` -> ``road``), or None."""
    for suffix in COMPLETION_SUFFIXES:
        if sensor.endswith(suffix) and sensor[:-len(suffix)] in outputs:
            return sensor[:-len(suffix)]
    return None


def rename_next(f: Formula, table: Mapping[str, str]) -> Formula:
    """``f`` with each next-state variable ``x'`` in ``table`` renamed to ``table[x]'``."""
    return map_vars(f, lambda v: Var(table[v.name], True) if v.primed and v.name in table else v)


def current(f: Formula) -> Formula:
    """``f`` read at the current step (every ``x'`` as ``x``)."""
    return map_vars(f, lambda v: Var(v.name, False))


@dataclass
class Ownership:
    """Received assumptions sorted by how the receiver keeps them; all are its guarantees (line 5)."""

    by_move: list[Clause] = field(default_factory=list)       # a next output of ours: as sent
    rewritten: list[Clause] = field(default_factory=list)     # through our activations (implies the literal)
    literal: list[Clause] = field(default_factory=list)       # over our sensors only, kept as sent

    @property
    def guarantees(self) -> list[Clause]:
        return self.by_move + self.rewritten + self.literal


def env_game(spec: Spec) -> Game:
    """The BDD game of ``spec``'s variables and environment safety only (for ``implied_by_rewrite``)."""
    return Game(Spec(inputs=list(spec.inputs), outputs=list(spec.outputs), env_safety=list(spec.env_safety),
                     source=spec.source))


def implied_by_rewrite(literal: Formula, rewrite: Formula, spec: Spec, position: Mapping[str, bool],
                       game: Game | None = None) -> bool:
    """Whether keeping ``rewrite`` (over next activations) at every step keeps ``literal`` (over next
    completion sensors) under ``spec``'s environment safety, from ``position`` (every input and output).

    Induction: L and R hold at ``position`` (read at the current step), and every transition the
    environment safety allows from a state where L and R hold ends where L holds. Both formulas must
    mention next-state variables only (a state property); otherwise False."""
    if any(not v.primed for f in (literal, rewrite) for v in variables(f)):
        return False
    now = {n: bool(position[n]) for n in spec.inputs + spec.outputs}
    if not (evaluate(current(literal), now, {}) and evaluate(current(rewrite), now, {})):
        return False
    game = game if game is not None else env_game(spec)
    broken = game.env_trans & game.to_bdd(current(literal)) & game.to_bdd(current(rewrite)) & ~game.to_bdd(literal)
    return broken == game.false


def split_by_ownership(clauses: list[Clause], spec: Spec, position: Mapping[str, bool]) -> Ownership:
    """Received assumptions (Alg. 4 line 5) by how the receiver with ``spec``, now at ``position``
    (inputs and outputs), keeps them (see the module docstring)."""
    mine = set(spec.outputs)
    out = Ownership()
    game: list[Game] = []  # built once, when a first rewrite is checked
    for clause in clauses:
        used = variables(clause.formula)
        if any(v.primed and v.name in mine for v in used):
            out.by_move.append(clause)
            continue
        sensed = {v.name for v in used if v.primed and v.name in spec.inputs}
        actions = {name: action_of(name, spec.outputs) for name in sensed}
        if sensed and all(actions.values()):
            formula = rename_next(clause.formula, actions)
            if not game:
                game.append(env_game(spec))
            if implied_by_rewrite(clause.formula, formula, spec, position, game[0]):
                out.rewritten.append(Clause(formula, formula_to_infix(formula), clause.file, clause.line))
                continue
        out.literal.append(clause)
    return out

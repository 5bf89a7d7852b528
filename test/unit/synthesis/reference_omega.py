"""Realizability of a Spec with the ``omega`` package (PyPI), semantics aligned with slugs.

How the two are aligned (see docs/synthesis_correctness.md for the reasoning):
- ``aut.moore = False``: the system picks its next outputs after seeing the next inputs (Mealy);
- ``aut.plus_one = False``: the step operator is ``EnvNext => (SysNext /\\ Target')``, so the system wins
  when the environment breaks its safety first, as in slugs' cpre;
- slugs' default init is ``qinit = '\\A \\E'`` (for all inputs satisfying EnvInit there are outputs
  with SysInit and winning); robotics semantics is ``'\\A \\A'`` with SysInit moved into EnvInit
  (omega asserts SysInit = TRUE there), i.e. every position satisfying both must be winning;
- omega's goals must be state predicates. A liveness clause with primed variables is a goal on
  transitions, so it gets an auxiliary Boolean ``_gN`` (system goal; owned by the system, whose action
  gains ``_gN' <=> goal``) or ``_aN`` (environment goal over inputs only; owned by the environment, whose
  action gains ``_aN' <=> goal``), and the liveness becomes ``[]<> _gN`` / ``[]<> _aN``: the aux variable
  is true exactly at the positions entered by a goal transition. The aux's initial value is free, which
  changes nothing (a goal met once does not count), so verdicts are preserved;
- an empty liveness section is ``[]<> TRUE`` (no env goal: ``<>[] FALSE``), as slugs adds.
"""
from __future__ import annotations

import contextlib
import io

from omega.games import gr1
from omega.symbolic import temporal
from random_specs import formula_has_prime

from ltl_stack.spec.formula import And, Const, Iff, Implies, Not, Or, Var, Xor


def to_tla(f) -> str:
    """A formula in omega's TLA+-like syntax."""
    if isinstance(f, Var):
        return f.name + ("'" if f.primed else "")
    if isinstance(f, Const):
        return "TRUE" if f.value else "FALSE"
    if isinstance(f, Not):
        return f"~ ({to_tla(f.arg)})"
    if isinstance(f, (And, Or)):
        if not f.args:
            return "TRUE" if isinstance(f, And) else "FALSE"
        joiner = r" /\ " if isinstance(f, And) else r" \/ "
        return "(" + joiner.join(to_tla(a) for a in f.args) + ")"
    left, right = to_tla(f.left), to_tla(f.right)
    if isinstance(f, Xor):
        return f"~ (({left}) <=> ({right}))"
    if isinstance(f, Implies):
        return f"(({left}) => ({right}))"
    if isinstance(f, Iff):
        return f"(({left}) <=> ({right}))"
    raise TypeError(f"not a formula: {f!r}")


def conjunction(clauses) -> str:
    return r" /\ ".join(f"({to_tla(c.formula)})" for c in clauses) or "TRUE"


def has_primed_liveness(spec) -> bool:
    return any(formula_has_prime(c.formula) for c in spec.env_liveness + spec.sys_liveness)


def omega_is_realizable(spec, *, robotics_semantics: bool = False) -> bool:
    """Realizability of ``spec`` computed by ``omega.games.gr1`` (aligned as described above)."""
    aut = temporal.Automaton()
    env_vars, sys_vars = list(spec.inputs), list(spec.outputs)
    env_action, sys_action = [conjunction(spec.env_safety)], [conjunction(spec.sys_safety)]
    env_goals, sys_goals = [], []
    for k, clause in enumerate(spec.env_liveness):
        if formula_has_prime(clause.formula):
            aux = f"_a{k}"
            env_vars.append(aux)
            env_action.append(f"({aux}' <=> ({to_tla(clause.formula)}))")
            env_goals.append(aux)
        else:
            env_goals.append(to_tla(clause.formula))
    for k, clause in enumerate(spec.sys_liveness):
        if formula_has_prime(clause.formula):
            aux = f"_g{k}"
            sys_vars.append(aux)
            sys_action.append(f"({aux}' <=> ({to_tla(clause.formula)}))")
            sys_goals.append(aux)
        else:
            sys_goals.append(to_tla(clause.formula))
    aut.declare_variables(**{name: "bool" for name in env_vars + sys_vars})
    aut.varlist = {"env": env_vars, "sys": sys_vars}
    env_init, sys_init = conjunction(spec.env_init), conjunction(spec.sys_init)
    if robotics_semantics:
        aut.init["env"] = f"({env_init}) /\\ ({sys_init})"
        aut.init["sys"] = "TRUE"
        aut.qinit = r"\A \A"
    else:
        aut.init["env"] = env_init
        aut.init["sys"] = sys_init
        aut.qinit = r"\A \E"
    aut.action["env"] = r" /\ ".join(env_action)
    aut.action["sys"] = r" /\ ".join(sys_action)
    aut.win["<>[]"] = aut.bdds_from(*[f"~ ({g})" for g in env_goals]) if env_goals else [aut.false]
    aut.win["[]<>"] = aut.bdds_from(*sys_goals) if sys_goals else [aut.true]
    aut.moore = False
    aut.plus_one = False
    with contextlib.redirect_stdout(io.StringIO()):  # omega prints why init fails
        z, _, _ = gr1.solve_streett_game(aut)
        return bool(gr1.is_realizable(z, aut))

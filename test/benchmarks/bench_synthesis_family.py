"""A scalable GR(1) family for the synthesis benchmark: n x n grid patrol with moving obstacles.

The robot (outputs: binary x and y coordinates) moves one cell up/down/left/right or stays, must
visit k goal cells infinitely often and must never share a cell with an obstacle. Obstacle o
(inputs: its binary column) moves left/right by at most one cell along its own row and is assumed
to reach both ends of that row infinitely often. Goals and the obstacles' liveness are state
predicates, so ``omega.games.gr1`` (state-based) solves the same game.

Also ``run_omega``: the same Spec solved by omega on its own BDD manager.
"""
from __future__ import annotations

import time

from ltl_stack.spec.formula import And, Const, Iff, Implies, Not, Or, Var
from ltl_stack.spec.model import Clause, Spec


def _bits(n: int) -> int:
    b = max(1, (n - 1).bit_length())
    if 1 << b != n:
        raise ValueError(f"grid side {n} must be a power of two")
    return b


def _eq_const(names: list[str], value: int, primed: bool = False):
    return And(tuple(Var(v, primed) if (value >> k) & 1 else Not(Var(v, primed)) for k, v in enumerate(names)))


def _eq_vars(a: list[str], b: list[str], a_primed: bool, b_primed: bool):
    return And(tuple(Iff(Var(x, a_primed), Var(y, b_primed)) for x, y in zip(a, b)))


def _step_at_most_one(names: list[str], n: int):
    """Conjunction over v of: (coordinate == v) -> (coordinate' in {v-1, v, v+1})."""
    parts = []
    for v in range(n):
        near = [w for w in (v - 1, v, v + 1) if 0 <= w < n]
        parts.append(Implies(_eq_const(names, v), Or(tuple(_eq_const(names, w, True) for w in near))))
    return And(tuple(parts))


def grid_patrol(n: int, goals: int, obstacles: int) -> Spec:
    b = _bits(n)
    rx = [f"rx{k}" for k in range(b)]
    ry = [f"ry{k}" for k in range(b)]
    ox = [[f"o{o}x{k}" for k in range(b)] for o in range(obstacles)]
    rows = [(o + 1) * n // (obstacles + 1) for o in range(obstacles)]
    cells = [(n - 1, n - 1), (0, n - 1), (n - 1, 0), (0, 0), (n // 2, 0), (n // 2, n - 1),
             (0, n // 2), (n - 1, n // 2)]
    if goals > len(cells):
        raise ValueError(f"at most {len(cells)} goals")
    file = f"grid_{n}x{n}_{goals}g_{obstacles}o"

    def clause(f, text):
        return Clause(f, text=text, file=file, line=0)

    spec = Spec(inputs=[v for o in ox for v in o], outputs=rx + ry, source=file)
    sys_safety = [
        clause(_step_at_most_one(rx, n), "robot x moves by at most one"),
        clause(_step_at_most_one(ry, n), "robot y moves by at most one"),
        clause(Or((_eq_vars(rx, rx, True, False), _eq_vars(ry, ry, True, False))), "no diagonal moves"),
    ]
    for o in range(obstacles):
        hit = And((_eq_const(ry, rows[o], True), _eq_vars(rx, ox[o], True, True)))
        sys_safety.append(clause(Not(hit), f"never on obstacle {o}"))
    env_safety = [clause(_step_at_most_one(ox[o], n), f"obstacle {o} moves by at most one")
                  for o in range(obstacles)]
    env_init = [clause(_eq_const(ox[o], n - 1), f"obstacle {o} starts right") for o in range(obstacles)]
    sys_init = [clause(And((_eq_const(rx, 0), _eq_const(ry, 0))), "robot starts at (0, 0)")]
    sys_liveness = [clause(And((_eq_const(rx, x), _eq_const(ry, y))), f"visit ({x}, {y})")
                    for x, y in cells[:goals]]
    env_liveness = []
    for o in range(obstacles):
        env_liveness.append(clause(_eq_const(ox[o], 0), f"obstacle {o} reaches the left end"))
        env_liveness.append(clause(_eq_const(ox[o], n - 1), f"obstacle {o} reaches the right end"))
    for name, clauses in [("env_init", env_init), ("sys_init", sys_init), ("env_safety", env_safety),
                          ("sys_safety", sys_safety), ("env_liveness", env_liveness),
                          ("sys_liveness", sys_liveness)]:
        spec = spec.with_section(name, clauses)
    return spec


def has_primed_liveness(spec: Spec) -> bool:
    from ltl_stack.spec.formula import variables

    return any(v.primed for c in spec.env_liveness + spec.sys_liveness for v in variables(c.formula))


def run_omega(spec: Spec, *, robotics_semantics: bool = False, reordering: bool = True) -> tuple[bool, float]:
    """Solve ``spec`` with ``omega.games.gr1`` (Mealy, env-violation-first, as slugs): (realizable, s).

    The BDDs of the spec are built on omega's manager by our ``Game`` (not timed); only omega's
    fixpoint and its initial-condition check are timed.
    """
    from omega.games import gr1
    from omega.symbolic import temporal as trl

    from ltl_stack.synthesis.game import Game

    rename = {v: f"v{k}" for k, v in enumerate(spec.propositions)}
    renamed = _rename(spec, rename)
    aut = trl.Automaton()
    aut.declare_variables(**{rename[v]: "bool" for v in spec.propositions})
    aut.varlist["env"] = [rename[v] for v in spec.inputs]
    aut.varlist["sys"] = [rename[v] for v in spec.outputs]
    game = Game(renamed, bdd=aut.bdd)
    aut.init["env"] = game.env_init
    aut.init["sys"] = game.sys_init
    aut.action["env"] = game.env_trans
    aut.action["sys"] = game.sys_trans
    aut.win["<>[]"] = [~a for a in game.env_goals]
    aut.win["[]<>"] = list(game.sys_goals)
    aut.moore = False
    aut.plus_one = False
    aut.qinit = "\\A \\A" if robotics_semantics else "\\A \\E"
    if robotics_semantics:
        aut.init["env"] = game.env_init & game.sys_init
        aut.init["sys"] = aut.true
    aut.bdd.configure(reordering=reordering)
    start = time.perf_counter()
    z, _, _ = gr1.solve_streett_game(aut)
    realizable = _omega_init_ok(gr1, z, aut)
    return realizable, time.perf_counter() - start


def _omega_init_ok(gr1, z, aut) -> bool:
    import contextlib
    import io

    with contextlib.redirect_stdout(io.StringIO()):  # omega prints why when unrealizable
        return bool(gr1.is_realizable(z, aut))


def _rename(spec: Spec, names: dict[str, str]) -> Spec:
    from ltl_stack.spec.formula import And as A
    from ltl_stack.spec.formula import Iff as I
    from ltl_stack.spec.formula import Implies as Im
    from ltl_stack.spec.formula import Not as N
    from ltl_stack.spec.formula import Or as O
    from ltl_stack.spec.formula import Xor as X

    memo: dict[int, object] = {}

    def ren(f):
        key = id(f)
        if key in memo:
            return memo[key]
        if isinstance(f, Var):
            out = Var(names[f.name], f.primed)
        elif isinstance(f, Const):
            out = f
        elif isinstance(f, N):
            out = N(ren(f.arg))
        elif isinstance(f, (A, O)):
            out = type(f)(tuple(ren(a) for a in f.args))
        elif isinstance(f, (X, Im, I)):
            out = type(f)(ren(f.left), ren(f.right))
        else:  # pragma: no cover
            raise TypeError(f)
        memo[key] = out
        return out

    out = Spec(inputs=[names[v] for v in spec.inputs], outputs=[names[v] for v in spec.outputs],
               source=spec.source)
    for section in ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness"):
        out = out.with_section(section, [Clause(ren(c.formula), c.text, c.file, c.line)
                                         for c in spec.section(section)])
    return out

"""Small GR(1) specs for the synthesis tests: a seeded random generator and a compact way to write specs.

``make_spec`` reads sections written in slugs' prefix notation (``| ! a b'``) with a parser of its own,
so that the tests of the reference solver do not depend on the spec package's readers.
"""
from __future__ import annotations

import random

from reference_solver import Grid

from ltl_stack.spec.formula import And, Const, Formula, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.model import SECTIONS, Clause, Spec


def parse_prefix(text: str) -> Formula:
    """A formula in slugs' prefix notation (operators ``! & | ^``, constants ``0 1``, ``name'`` primes)."""
    tokens = text.split()
    position = 0

    def parse() -> Formula:
        nonlocal position
        if position >= len(tokens):
            raise ValueError(f"premature end of {text!r}")
        token = tokens[position]
        position += 1
        if token == "!":
            return Not(parse())
        if token in ("&", "|", "^"):
            left = parse()
            right = parse()
            return {"&": And((left, right)), "|": Or((left, right)), "^": Xor(left, right)}[token]
        if token in ("0", "1"):
            return Const(token == "1")
        if token.endswith("'"):
            return Var(token[:-1], True)
        return Var(token)

    formula = parse()
    if position != len(tokens):
        raise ValueError(f"stray tokens in {text!r}")
    return formula


def make_spec(inputs: list[str], outputs: list[str], file: str = "hand.slugsin", **sections: list[str]) -> Spec:
    """A Spec whose sections are lists of prefix formulas; clause i of a section gets a distinct line."""
    spec = Spec(inputs=list(inputs), outputs=list(outputs), source=file)
    line = 1
    for name in SECTIONS:
        clauses = []
        for text in sections.get(name, []):
            clauses.append(Clause(parse_prefix(text), text=text, file=file, line=line))
            line += 1
        spec = spec.with_section(name, clauses)
    unknown = set(sections) - set(SECTIONS)
    if unknown:
        raise ValueError(f"unknown sections {sorted(unknown)}")
    return spec


def formula_has_prime(formula: Formula) -> bool:
    stack = [formula]
    while stack:
        node = stack.pop()
        if isinstance(node, Var):
            if node.primed:
                return True
        elif isinstance(node, Not):
            stack.append(node.arg)
        elif isinstance(node, (And, Or)):
            stack.extend(node.args)
        elif isinstance(node, (Xor, Implies, Iff)):
            stack.extend((node.left, node.right))
    return False


class _Generator:
    def __init__(self, rng: random.Random, inputs: list[str], outputs: list[str]):
        self.rng = rng
        self.inputs = inputs
        self.outputs = outputs

    def literal(self, atoms: list[tuple[str, bool]]) -> Formula:
        name, primed = self.rng.choice(atoms)
        var = Var(name, primed)
        return Not(var) if self.rng.random() < 0.5 else var

    def formula(self, atoms: list[tuple[str, bool]], leaves: int, must: list[tuple[str, bool]] = ()) -> Formula:
        """A random formula with ``leaves`` literals; one of them is drawn from ``must`` when given."""
        parts = [self.literal(atoms) for _ in range(leaves)]
        if must:
            parts[self.rng.randrange(leaves)] = self.literal(list(must))
        while len(parts) > 1:
            i = self.rng.randrange(len(parts) - 1)
            left, right = parts[i], parts[i + 1]
            roll = self.rng.random()
            if roll < 0.35:
                node = Or((left, right))
            elif roll < 0.6:
                node = Implies(left, right)
            elif roll < 0.85:
                node = And((left, right))
            elif roll < 0.93:
                node = Iff(left, right)
            else:
                node = Xor(left, right)
            parts[i:i + 2] = [node]
        return parts[0]

    def atoms(self, inputs: bool = True, outputs: bool = True, next_inputs: bool = False,
              next_outputs: bool = False) -> list[tuple[str, bool]]:
        result = []
        if inputs:
            result += [(n, False) for n in self.inputs]
        if outputs:
            result += [(n, False) for n in self.outputs]
        if next_inputs:
            result += [(n, True) for n in self.inputs]
        if next_outputs:
            result += [(n, True) for n in self.outputs]
        return result


def random_spec(seed: int, max_inputs: int = 4, max_outputs: int = 4) -> Spec:
    """A seeded random spec: 2..max inputs and outputs, all six sections non-empty and non-constant,
    primes in both safety sections and in the system liveness (and often in the environment liveness).

    Env safety and env liveness never mention primed outputs (slugs forbids it)."""
    rng = random.Random(seed)
    inputs = [f"i{k}" for k in range(rng.randint(2, max_inputs))]
    outputs = [f"o{k}" for k in range(rng.randint(2, max_outputs))]
    gen = _Generator(rng, inputs, outputs)
    file = f"random_{seed}.slugsin"

    grid = Grid(inputs, outputs)
    lines = iter(range(1, 1000))

    def clauses(count: int, make) -> list[Clause]:
        """``count`` clauses, none of them constant (a tautology would make its section trivial)."""
        result = []
        while len(result) < count:
            formula = make()
            values = grid.evaluate(formula)
            if values.all() or not values.any():
                continue
            line = next(lines)
            result.append(Clause(formula, text=f"random clause {line}", file=file, line=line))
        return result

    env_init = clauses(1, lambda: gen.formula(gen.atoms(outputs=False), rng.randint(1, 2)))
    sys_init = clauses(1, lambda: gen.formula(gen.atoms(inputs=False), rng.randint(1, 2)))
    env_safety = clauses(rng.randint(1, 2), lambda: gen.formula(
        gen.atoms(next_inputs=True), rng.randint(2, 3), must=gen.atoms(False, False, next_inputs=True)))
    sys_safety = clauses(rng.randint(1, 3), lambda: gen.formula(
        gen.atoms(next_inputs=True, next_outputs=True), rng.randint(2, 3),
        must=gen.atoms(False, False, next_outputs=True)))
    env_liveness = clauses(rng.randint(1, 2), lambda: gen.formula(
        gen.atoms(next_inputs=True), rng.randint(1, 2)))
    sys_liveness = clauses(rng.randint(1, 2), lambda: gen.formula(
        gen.atoms(next_inputs=True, next_outputs=True), rng.randint(1, 3),
        must=gen.atoms(False, False, next_inputs=True, next_outputs=True)))
    spec = Spec(inputs=inputs, outputs=outputs, env_init=env_init, sys_init=sys_init, env_safety=env_safety,
                sys_safety=sys_safety, env_liveness=env_liveness, sys_liveness=sys_liveness, source=file)
    return spec

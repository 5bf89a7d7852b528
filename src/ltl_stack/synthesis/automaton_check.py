"""Is a saved strategy a strategy for this spec? Checked when a strategy file is loaded.

A strategy made from an older version of a spec loads fine and then runs outputs the new spec
forbids. ``check_automaton`` refuses it, naming the file, the state or edge and the clause
(``file:line``):

- the automaton's inputs and outputs are the spec's (same names, the spec's inputs as inputs);
- every state has a value for each of them; ids are unique; initial ids and successors exist;
- every initial state satisfies env_init and sys_init;
- every edge (state -> successor, the successor's inputs being the environment's move) satisfies
  sys safety, and env safety unless it is a recovery edge (``AutomatonState.recovery``, the answer
  to inputs that break the assumptions).

Edges are evaluated all at once per clause (``ops.evaluate_many``, one byte per edge), so a
strategy with millions of edges is checked in seconds.
"""
from __future__ import annotations

from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.ops import evaluate_many
from ltl_stack.synthesis.automaton import Automaton, AutomatonState
from ltl_stack.synthesis.errors import StrategyFileError


def load_checked(path: str, spec: Spec) -> Automaton:
    """``Automaton.load`` (the spec's inputs as the inputs of slugs' layout) and ``check_automaton``."""
    automaton = Automaton.load(path, inputs=list(spec.inputs))
    check_automaton(automaton, spec, str(path))
    return automaton


def check_automaton(automaton: Automaton, spec: Spec, file: str = "") -> None:
    """Raise ``StrategyFileError`` (``Exit.BAD_INPUT``) naming what breaks ``spec``; see the module doc."""
    where = file or automaton.path or "strategy"
    _check_names(automaton, spec, where)
    by_id = _check_ids(automaton, where)
    _check_initial(automaton, spec, by_id, where)
    _check_edges(automaton, spec, by_id, where)


def _check_names(automaton: Automaton, spec: Spec, where: str) -> None:
    if list(automaton.inputs) != list(spec.inputs) or list(automaton.outputs) != list(spec.outputs):
        if set(automaton.inputs) != set(spec.inputs) or set(automaton.outputs) != set(spec.outputs):
            raise StrategyFileError(
                f"{where}: the strategy's propositions (inputs {', '.join(automaton.inputs) or '-'}; outputs "
                f"{', '.join(automaton.outputs) or '-'}) are not the spec's (inputs {', '.join(spec.inputs) or '-'}; "
                f"outputs {', '.join(spec.outputs) or '-'}, {spec.source})")
    for state in automaton.states:
        for part, names in ((state.inputs, spec.inputs), (state.outputs, spec.outputs)):
            missing = [n for n in names if not isinstance(part.get(n), bool)]
            if missing:
                raise StrategyFileError(f"{where}: state {state.id} has no true/false value for "
                                        f"{', '.join(missing[:5])}")


def _check_ids(automaton: Automaton, where: str) -> dict[int, AutomatonState]:
    by_id: dict[int, AutomatonState] = {}
    for state in automaton.states:
        if state.id in by_id:
            raise StrategyFileError(f"{where}: state id {state.id} is used twice")
        by_id[state.id] = state
    if not automaton.initial:
        raise StrategyFileError(f"{where}: no initial state")
    for sid in automaton.initial:
        if sid not in by_id:
            raise StrategyFileError(f"{where}: initial state {sid} does not exist")
    for state in automaton.states:
        for target in state.successors:
            if target not in by_id:
                raise StrategyFileError(f"{where}: state {state.id} has a successor {target} that does not exist")
        stray = set(state.recovery) - set(state.successors)
        if stray:
            raise StrategyFileError(f"{where}: state {state.id} lists recovery successors {sorted(stray)} "
                                    "that are not among its successors")
    return by_id


def _broken(clause: Clause, section: str) -> str:
    text = " ".join((clause.text or "(no text)").split())
    return f"{section} {clause.location}: {text[:120]}"


def _check_initial(automaton: Automaton, spec: Spec, by_id: dict[int, AutomatonState], where: str) -> None:
    for sid in automaton.initial:
        state = by_id[sid]
        values = {n: int(v) for n, v in {**state.inputs, **state.outputs}.items()}
        for section in ("env_init", "sys_init"):
            for clause in spec.section(section):
                if not evaluate_many(clause.formula, values, None, 1):
                    raise StrategyFileError(f"{where}: initial state {sid} breaks {_broken(clause, section)}")


def _check_edges(automaton: Automaton, spec: Spec, by_id: dict[int, AutomatonState], where: str) -> None:
    edges = [(s, by_id[t], t in s.recovery) for s in automaton.states for t in s.successors]
    if not edges:
        return
    names = [*spec.inputs, *spec.outputs]
    # one byte lane per edge: bit 8k of a value is the variable's value on edge k
    lanes = int.from_bytes(b"\x01" * len(edges), "little")
    current = {n: int.from_bytes(bytes(int(s.inputs[n] if n in s.inputs else s.outputs[n]) for s, _, _ in edges),
                                 "little") for n in names}
    nxt = {n: int.from_bytes(bytes(int(t.inputs[n] if n in t.inputs else t.outputs[n]) for _, t, _ in edges),
                             "little") for n in names}
    ordinary = int.from_bytes(bytes(int(not rec) for _, _, rec in edges), "little")
    for section, scope in (("env_safety", ordinary), ("sys_safety", lanes)):
        for clause in spec.section(section):
            failed = ~evaluate_many(clause.formula, current, nxt, lanes) & scope
            if failed:
                k = (failed & -failed).bit_length() // 8
                source, target, _ = edges[k]
                what = "an environment move the spec does not allow" if section == "env_safety" else "the move"
                raise StrategyFileError(f"{where}: edge {source.id} -> {target.id} ({what}) breaks "
                                        f"{_broken(clause, section)}")

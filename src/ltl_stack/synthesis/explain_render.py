"""The explanation of an unrealizable spec (``explain.explain``) for people and tools.

``explanation_text`` is the report ``synthesize --explain`` prints, ``explanation_dict`` its JSON
data (``--json``); ``counterstrategy_json`` and ``counterstrategy_dot`` are the files of
``--counterstrategy``. Clauses are named by ``file:line`` with their text and, when it says more,
their formula in words (``formula_text``); the words of a clause with shared subformulas name them
(``… where B1 = …``), so it stays as long as the clause.
"""
from __future__ import annotations

from collections.abc import Mapping

from ltl_stack.spec.formula_text import clause_in_words
from ltl_stack.spec.model import Clause
from ltl_stack.synthesis.explain import DEADLOCK, INIT, LIVELOCK, Counterstrategy, Explanation

#: characters of a clause's text and English in the text report (generated specs have long clauses;
#: the JSON data keeps them whole)
MAX_TEXT = 160


def in_words(clause: Clause) -> str:
    """The clause's formula in words (no section word)."""
    return clause_in_words(clause)


def _shorten(text: str) -> str:
    return text if len(text) <= MAX_TEXT else text[:MAX_TEXT - 3] + "..."


def clause_line(clause: Clause, section: str | None = None) -> str:
    """``file:line: text`` (plus the formula in words in parentheses when it says more); long
    clauses are shortened."""
    text = _shorten(clause.text or "(no text)")
    words = _shorten(in_words(clause))
    tag = f"[{section}] " if section else ""
    line = f"{clause.location}: {tag}{text}"
    if words and words.strip() != text.strip():
        line += f"    ({words})"
    return line


def clause_dict(clause: Clause, section: str) -> dict:
    return {"section": section, "file": clause.file, "line": clause.line, "text": clause.text,
            "english": in_words(clause)}


def _true_names(valuation: Mapping[str, bool]) -> str:
    names = [k for k, v in valuation.items() if v]
    return "{" + ", ".join(names) + "}"


def explanation_dict(e: Explanation) -> dict:
    """The explanation as JSON-able data."""
    return {
        "source": e.source,
        "realizable": e.realizable,
        "robotics_semantics": e.robotics_semantics,
        "kind": None if e.kind is None else str(e.kind),
        "losing_initial": e.losing_initial,
        "init_clauses": [clause_dict(c, "sys_init") for c in e.init_clauses],
        "realizable_with_default_init": e.realizable_with_default_init,
        "deadlock": None if e.deadlock is None else {
            **{k: v for k, v in e.deadlock.items() if k != "clauses"},
            "clauses": [clause_dict(c, "sys_safety") for c in e.deadlock["clauses"]]},
        "failing_goals": [clause_dict(c, "sys_liveness") for c in e.failing_goals],
        "core": [clause_dict(c, s) for s, c in e.core],
        "core_candidates": e.core_candidates,
        "cooperative_possible": e.cooperative_possible,
        "assumption_core": [clause_dict(c, s) for s, c in e.assumption_core],
        "checks": e.checks,
        "counterstrategy": None if e.counterstrategy is None else counterstrategy_json(e.counterstrategy),
    }


def explanation_text(e: Explanation) -> str:
    """The explanation as the report ``synthesize --explain`` prints."""
    semantics = "robotics init semantics" if e.robotics_semantics else "slugs' default init semantics"
    if e.realizable:
        return f"{e.source}: realizable ({semantics}); nothing to explain.\n"
    out = [f"{e.source}: unrealizable ({semantics})."]
    if e.kind == INIT:
        out.append(f"Initial condition: for the initial inputs {_true_names(e.losing_initial or {})} "
                   "no initial output satisfies the system's initial condition:")
        out += [f"  {clause_line(c, 'sys_init')}" for c in e.init_clauses]
    elif e.kind == DEADLOCK:
        out.append("Deadlock: the environment can force the robot into a position where every move "
                   "violates its safety requirements.")
    else:
        out.append("Livelock: the robot can always stay safe, but the environment, while meeting all of "
                   "its assumptions, can keep it from reaching a goal forever.")
    if e.losing_initial is not None and e.kind != INIT:
        where = "position" if e.robotics_semantics else "inputs"
        out.append(f"The environment wins from the initial {where} {_true_names(e.losing_initial)} "
                   "(true propositions listed).")
    if e.realizable_with_default_init:
        out.append("It is realizable with slugs' default init semantics: some initial positions allowed by "
                   "sys_init are losing; restricting sys_init to the winning ones fixes it.")
    if e.deadlock is not None:
        d = e.deadlock
        if d["steps"]:
            moves = "; ".join(f"env {_true_names(m['inputs_next'])}, robot {_true_names(m['outputs_next'])}"
                              for m in d["path"][:6])
            more = " ..." if d["steps"] > 6 else ""
            out.append(f"From {_true_names(d['start'])} the environment forces it within {d['steps']} "
                       f"move(s), whatever the robot answers; e.g. {moves}{more}.")
        out.append(f"At {_true_names(d['position'])}, when the environment plays "
                   f"{_true_names(d['inputs_next'])}, every next output breaks one of:")
        out += [f"  {clause_line(c, 'sys_safety')}" for c in d["clauses"]]
    if e.failing_goals:
        out.append("Goals the robot cannot ensure even on their own (with all safety requirements):")
        out += [f"  {clause_line(c, 'sys_liveness')}" for c in e.failing_goals]
    elif e.kind == LIVELOCK:
        out.append("Each goal can be ensured on its own; the goals fail together.")
    out.append(f"Minimal unrealizable subset of the robot's requirements ({len(e.core)} of "
               f"{e.core_candidates} safety/goal clauses; removing any one makes it realizable):")
    if e.core:
        out += [f"  {clause_line(c, s)}" for s, c in e.core]
    else:
        out.append("  (none: the initial condition alone is unrealizable)")
    if e.cooperative_possible is False:
        out.append("Even a cooperative environment cannot let the robot meet its requirements: they conflict "
                   "with these assumptions (a minimal subset; weakening one of them matters):")
        out += [f"  {clause_line(c, s)}" for s, c in e.assumption_core] or [
            "  (none: the robot's requirements conflict among themselves)"]
    elif e.cooperative_possible:
        out.append("A cooperative environment would let the robot meet its requirements: the environment "
                   "can prevent it. Stronger assumptions that rule out the counterstrategy's behaviour "
                   "are a way to make it realizable.")
    if e.counterstrategy is not None:
        cs = e.counterstrategy
        stuck = sum(s.robot_stuck for s in cs.states)
        out.append(f"Environment counterstrategy: {len(cs.states)} states, {stuck} where the robot has no "
                   f"safe move{' (truncated)' if cs.truncated else ''}.")
    out.append(f"({e.checks} realizability checks)")
    return "\n".join(out) + "\n"


def counterstrategy_json(cs: Counterstrategy) -> dict:
    """The counterstrategy file's data (``goals`` as ``file:line: text`` of each system goal)."""
    goals = [clause_line(c) for c in cs.goals] or ["(no goal: true)"]
    return {"inputs": cs.inputs, "outputs": cs.outputs, "initial": cs.initial,
            "goals": goals, "truncated": cs.truncated,
            "states": [{"id": s.id, "inputs": s.inputs, "outputs": s.outputs,
                        "blocked_goal": s.blocked_goal, "env_goal": s.env_goal,
                        "env_move": s.env_move, "robot_stuck": s.robot_stuck,
                        "successors": s.successors} for s in cs.states]}


def counterstrategy_dot(cs: Counterstrategy, name: str = "counterstrategy") -> str:
    """The counterstrategy as Graphviz DOT (robot-stuck states filled, initial ones double-bordered)."""
    lines = [f"digraph {name} {{", "  rankdir=LR;", '  node [shape=box, fontname="monospace"];']
    for s in cs.states:
        label = f"{s.id}: in {_true_names(s.inputs)}\\nout {_true_names(s.outputs)}\\n" \
                f"blocks goal {s.blocked_goal}"
        if s.env_move is not None:
            label += f"\\nenv plays {_true_names(s.env_move)}"
        style = ", style=filled, fillcolor=\"#f4cccc\"" if s.robot_stuck else ""
        shape = ", peripheries=2" if s.id in cs.initial else ""
        lines.append(f'  n{s.id} [label="{label}"{style}{shape}];')
        if s.robot_stuck:
            lines.append(f'  stuck{s.id} [label="robot has no safe move", shape=plaintext];')
            lines.append(f"  n{s.id} -> stuck{s.id};")
        for t in s.successors:
            lines.append(f"  n{s.id} -> n{t};")
    lines.append("}")
    return "\n".join(lines) + "\n"

"""GR(1) clauses back to Structured English sentences that ``english_reader`` reads again.

``clause_to_sentence(clause, section, decl)`` writes one clause as one sentence: ``Always move``,
``If you are sensing person then do stop``, ``If C then visit R``, ``Assume always …``,
``Robot starts with …``. Reading the sentence back gives an equivalent clause in the same section
(the tense says current or next state, ``you are in R`` / ``you have finished a`` the completions).
``spec_sentences(english)`` renders a read English spec sentence by sentence, recognising the
forms that give several clauses (memory, lists of goals, ``Start in``, mutual exclusion), so the
result reads like the input. ``append_sentences(path, sentences)`` adds sentences — suggestions
of the graph analysis, learned assumptions — to an English spec file, atomically and only if the
whole file still reads.

Formulas that a sentence cannot say raise ``ValueError``: goals over next-state values (the
fairness clauses of [75] are generated, not written), and robot guarantees that do not constrain
anything the robot does next.
"""
from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.fileio import write_atomic
from ltl_stack.inputs import read_text
from ltl_stack.spec.activation_completion import ACTION_COMPLETION, REGION_COMPLETION
from ltl_stack.spec.english_files import read_english
from ltl_stack.spec.english_reader import Declarations, EnglishSpec
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import And, Const, Formula, Iff, Implies, Not, Or, Var, Xor, walk
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.ops import fold

_PRESENT = {"sensor": "you are sensing", "robot": "you are activating", "region": "you are in",
            "done": "you have finished"}
_PAST = {"sensor": "you were sensing", "robot": "you were activating", "region": "you were in",
         "done": "you had finished"}
_PRESENT_NOT = {"sensor": "you are not sensing", "robot": "you are not activating", "region": "you are not in",
                "done": "you have not finished"}
_PAST_NOT = {"sensor": "you were not sensing", "robot": "you were not activating", "region": "you were not in",
             "done": "you had not finished"}


def declarations_of(spec: Spec) -> Declarations:
    """Declarations inferred from a spec's names: ``a``/``a_ac`` and ``R``/``R_rc`` pairs, sensors, actions."""
    decl = Declarations()
    outputs = set(spec.outputs)
    for name in spec.inputs:
        if name.endswith(REGION_COMPLETION) and name[:-len(REGION_COMPLETION)] in outputs:
            decl.regions.append(name[:-len(REGION_COMPLETION)])
            decl.kind_of[name] = "completions"
        elif name.endswith(ACTION_COMPLETION) and name[:-len(ACTION_COMPLETION)] in outputs:
            decl.completion_actions.append(name[:-len(ACTION_COMPLETION)])
            decl.kind_of[name] = "completions"
        else:
            decl.sensors.append(name)
            decl.kind_of[name] = "sensors"
    for name in spec.outputs:
        if name in decl.regions:
            decl.kind_of[name] = "regions"
        elif name in decl.completion_actions:
            decl.kind_of[name] = "completion_actions"
        else:
            decl.actions.append(name)
            decl.kind_of[name] = "actions"
    return decl


#: rendered text longer than this is refused (a DAG with shared subformulas can unfold hugely)
MAX_SENTENCE = 100_000


def _lower(f: Formula) -> Formula:
    """``f`` with only not/and/or (the connectives of sentences): ``a -> b`` is ``not a or b``."""
    def combine(node: Formula, kids: tuple) -> Formula:
        if isinstance(node, Implies):
            return Or((Not(kids[0]), kids[1]))
        if isinstance(node, Iff):
            return Or((And((kids[0], kids[1])), And((Not(kids[0]), Not(kids[1])))))
        if isinstance(node, Xor):
            return Or((And((kids[0], Not(kids[1]))), And((Not(kids[0]), kids[1]))))
        if isinstance(node, Not):
            return Not(kids[0])
        if isinstance(node, And):
            return And(kids)
        if isinstance(node, Or):
            return Or(kids)
        return node
    return fold(f, combine)


class _Writer:
    """Renders formulas as sentence parts for one spec's declarations.

    ``bare`` style writes a present-tense sensor or robot proposition as its name (``object``,
    ``not pickup``), as memory events, ``do`` and initial conditions read them; every other
    proposition gets its phrase (``you were in R``, ``finished pickup``). Operands that start with
    a phrase go last in a list, so that no bare name falls under a phrase.
    """

    def __init__(self, decl: Declarations):
        self.decl = decl
        self.completion_of = {a + ACTION_COMPLETION: (a, "done") for a in decl.completion_actions}
        self.completion_of.update({r + REGION_COMPLETION: (r, "region") for r in decl.regions})
        self.outputs = set(decl.outputs)

    def _atom(self, var: Var) -> tuple[str, str]:
        """(name as written, kind) for the phrase: kind is sensor, robot, region or done."""
        if var.name in self.completion_of:
            return self.completion_of[var.name]
        if var.name in self.outputs:
            return var.name, "robot"
        if var.name in self.decl.kind_of:
            return var.name, "sensor"
        raise ValueError(f"'{var.name}' is not declared in this spec")

    @staticmethod
    def _past(var: Var, mode: str) -> bool:
        """True for the past tense; refuses what the mode cannot say."""
        if mode == "safety":
            return not var.primed
        if var.primed:
            raise ValueError(f"{var.name}' (the next state) cannot be said in a goal or an initial condition")
        return False

    def _literal(self, var: Var, negated: bool, mode: str, bare: bool) -> tuple[str, bool]:
        """(text, starts with a phrase)."""
        name, kind = self._atom(var)
        past = self._past(var, mode)
        if bare and not past and kind in ("sensor", "robot"):
            return (f"not {name}" if negated else name), False
        if bare and not past and kind == "done":
            return (f"not finished {name}" if negated else f"finished {name}"), True
        table = (_PAST_NOT if past else _PRESENT_NOT) if negated else (_PAST if past else _PRESENT)
        return f"{table[kind]} {name}", True

    def _group(self, node: Formula, mode: str, bare: bool) -> tuple[str, str, bool, list[str]] | None:
        """``a or b or c`` of positive literals that share one phrase: (connective, kind, past, names)."""
        if bare or not isinstance(node, (And, Or)) or len(node.args) < 2:
            return None
        if not all(isinstance(a, Var) for a in node.args):
            return None
        kinds = [self._atom(a)[1] for a in node.args]
        # sensing and activating read a name the same way: one phrase covers both (Spec. 3 line 6)
        plain = {"sensor": "plain", "robot": "plain"}
        shapes = {(plain.get(k, k), self._past(a, mode)) for k, a in zip(kinds, node.args)}
        if len(shapes) != 1:
            return None
        kind, past = shapes.pop()
        if kind == "plain":  # the phrase of the first name (the reader checks the name right after it)
            kind = kinds[0]
        return ("and" if isinstance(node, And) else "or"), kind, past, [self._atom(a)[0] for a in node.args]

    def expression(self, f: Formula, mode: str, bare: bool = False) -> str:
        """A condition: ``you are sensing a and you were in R`` (``bare``: ``a and not b``)."""
        f = _lower(f)
        # (text, simple, phrase first); simple texts need no parentheses as an operand of and/or
        results: dict[int, tuple[str, bool, bool]] = {}
        stack: list[tuple[Formula, bool]] = [(f, False)]
        while stack:
            node, ready = stack.pop()
            if id(node) in results:
                continue
            kids = self._children(node, mode, bare)
            if not ready:
                stack.append((node, True))
                stack.extend((k, False) for k in kids if id(k) not in results)
                continue
            text = self._combine(node, [results[id(k)] for k in kids], mode, bare)
            if len(text[0]) > MAX_SENTENCE:
                raise ValueError("the formula is too large to write as a sentence")
            results[id(node)] = text
        return results[id(f)][0]

    def _children(self, node: Formula, mode: str, bare: bool) -> tuple[Formula, ...]:
        if isinstance(node, Not):
            if isinstance(node.arg, Var) or self._group(node.arg, mode, bare) is not None:
                return ()
            return (node.arg,)
        if isinstance(node, (And, Or)):
            return () if self._group(node, mode, bare) is not None else node.args
        return ()

    def _combine(self, node: Formula, kids: list[tuple[str, bool, bool]], mode: str,
                 bare: bool) -> tuple[str, bool, bool]:
        if isinstance(node, Var):
            return (*self._literal(node, False, mode, bare)[:1], True, self._literal(node, False, mode, bare)[1])
        if isinstance(node, Const):
            return ("true" if node.value else "false"), True, False
        if isinstance(node, Not):
            if isinstance(node.arg, Var):
                text, phrase = self._literal(node.arg, True, mode, bare)
                return text, True, phrase
            group = self._group(node.arg, mode, bare)
            if group is not None:
                connective, kind, past, names = group
                return f"{(_PAST_NOT if past else _PRESENT_NOT)[kind]} ({f' {connective} '.join(names)})", False, True
            text, simple, _ = kids[0]
            return f"not ({text})", True, False
        group = self._group(node, mode, bare)
        if group is not None:
            connective, kind, past, names = group
            return f"{(_PAST if past else _PRESENT)[kind]} {f' {connective} '.join(names)}", False, True
        if not kids:
            return ("true" if isinstance(node, And) else "false"), True, False
        if len(kids) == 1:
            return kids[0]
        if bare:  # operands that start with a phrase last: a bare name after one would fall under it
            kids = [k for k in kids if not k[2]] + [k for k in kids if k[2]]
        word = " and " if isinstance(node, And) else " or "
        return word.join(t if simple else f"({t})" for t, simple, _ in kids), False, kids[0][2]

    # -- requirement forms --------------------------------------------------------------------

    def robot_next_only(self, f: Formula) -> bool:
        """Only next-state robot activations (no completions): can be said with ``do``."""
        names = [v for v in walk(f) if isinstance(v, Var)]
        return bool(names) and all(v.primed and v.name in self.outputs for v in names)

    def do(self, f: Formula) -> str:
        """``do a and b`` / ``do (not a or b)``: bare names read as the next state inside ``do``."""
        if isinstance(f, Not):
            inner = f.arg
            text = self.expression(inner, "safety", bare=True)
            return f"do not {text}" if isinstance(inner, Var) else f"do not ({text})"
        text = self.expression(f, "safety", bare=True)
        return f"do ({text})" if text.startswith("not ") else f"do {text}"

    def requirement(self, f: Formula) -> str:
        return self.do(f) if self.robot_next_only(f) else self.expression(f, "safety")

    def goal(self, f: Formula, env: bool) -> str:
        """``visit R`` for ``R & R_rc``, else ``infinitely often …`` (``do`` when it mentions sensing)."""
        region = self.visited(f)
        if region is not None:
            return f"visit {region}"
        text = self.expression(f, "goal", bare=True)
        if not env and any(isinstance(v, Var) and v.name not in self.outputs for v in walk(f)):
            return f"infinitely often do ({text})"
        return f"infinitely often {text}"

    def visited(self, f: Formula) -> str | None:
        if isinstance(f, And) and len(f.args) == 2 and all(isinstance(a, Var) and not a.primed for a in f.args):
            a, b = f.args
            for r, c in ((a, b), (b, a)):
                if r.name in self.decl.regions and c.name == r.name + REGION_COMPLETION:
                    return r.name
        return None


def clause_to_sentence(clause: Clause | Formula, section: str, decl: Declarations | Spec) -> str:
    """One clause of ``section`` as a sentence that reads back as an equivalent clause there."""
    if isinstance(decl, Spec):
        decl = declarations_of(decl)
    f = clause.formula if isinstance(clause, Clause) else clause
    env = section.startswith("env_")
    body = _sentence_body(_Writer(decl), f, section, env)
    if env and not section.endswith("_init"):
        return f"Assume {body}"
    return _capital(body)


def _sentence_body(w: _Writer, f: Formula, section: str, env: bool) -> str:
    if section.endswith("_init"):
        return f"{'environment' if env else 'robot'} starts with {w.expression(f, 'init', bare=True)}"
    if section.endswith("_liveness"):
        condition, goal = _split_condition(f)
        if condition is not None:
            g = w.visited(goal)
            then = f"visit {g}" if g else f"infinitely often {w.expression(goal, 'goal', bare=True)}"
            return f"if {w.expression(condition, 'goal')} then {then}"
        return w.goal(f, env)
    if section not in ("env_safety", "sys_safety"):
        raise ValueError(f"unknown section {section!r}")
    robot_next = any(isinstance(v, Var) and v.primed and v.name in w.outputs for v in walk(f))
    if not env and not robot_next:
        raise ValueError("a robot guarantee that constrains nothing the robot does next cannot be written as a "
                         "sentence (it would read as an assumption)")
    if isinstance(f, Iff):
        return f"{w.requirement(f.left)} if and only if {w.expression(f.right, 'safety')}"
    condition, requirement = _split_condition(f)
    if condition is not None:
        return f"if {w.expression(condition, 'safety')} then {w.requirement(requirement)}"
    if w.robot_next_only(f):
        return f"always {w.expression(f, 'safety', bare=True)}"
    return f"always {w.expression(f, 'safety')}"


def _split_condition(f: Formula) -> tuple[Formula | None, Formula]:
    """``a -> b`` and slugs' ``!a | b`` as (a, b); anything else as (None, f)."""
    if isinstance(f, Implies):
        return f.left, f.right
    if isinstance(f, Or) and len(f.args) >= 2 and isinstance(f.args[0], Not):
        rest = f.args[1] if len(f.args) == 2 else Or(f.args[1:])
        return f.args[0].arg, rest
    return None, f


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def spec_sentences(english: EnglishSpec) -> list[str]:
    """The sentences of a read English spec rendered from its GR(1) clauses, one per input sentence.

    Clauses are grouped by the sentence they came from; forms that compile to several clauses
    (memory, visit lists, ``Start in``, mutual exclusion) are recognised and written as one
    sentence. Generated clauses (regions, completions) are left out: the declarations make them.
    """
    decl = english.declarations
    by_line: dict[int, list[tuple[str, Clause]]] = {}
    for section in ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness"):
        for clause in english.spec.section(section):
            if clause.line in english.sentences and clause.file == english.spec.source:
                by_line.setdefault(clause.line, []).append((section, clause))
    w = _Writer(decl)
    out = []
    for line in sorted(by_line):
        out.extend(_render_group(by_line[line], w, decl))
    return out


def _render_group(group: list[tuple[str, Clause]], w: _Writer, decl: Declarations) -> list[str]:
    sections = [s for s, _ in group]
    formulas = [c.formula for _, c in group]
    start = _start_in(group, decl)
    if start is not None:
        return [start]
    memory = _memory(group, w)
    if memory is not None:
        return [memory]
    if sorted(sections) in (["sys_init", "sys_safety"], ["env_init", "env_safety"]):
        names = _exclusive(next(f for s, f in zip(sections, formulas) if s.endswith("safety")))
        if names:
            listed = ", ".join(names[:-1]) + " and " + names[-1]
            return [f"{'Assume ' if sections[0].startswith('env') else ''}{listed} are mutually exclusive"]
    if len(group) > 1 and all(s == sections[0] and s.endswith("liveness") for s in sections):
        visits = [_split_condition(f) for f in formulas]
        regions = [w.visited(g) for _, g in visits]
        conditions = {w.expression(c, "goal") if c is not None else "" for c, _ in visits}
        if all(regions) and len(conditions) == 1:
            condition = conditions.pop()
            listed = ", ".join(regions[:-1]) + " and " + regions[-1]
            prefix = "Assume " if sections[0].startswith("env") else ""
            if condition:
                return [f"{prefix}If {condition} then visit {listed}"]
            return [f"{prefix}{'v' if prefix else 'V'}isit {listed}"]
    return [clause_to_sentence(c, s, decl) for s, c in group]


def _start_in(group: list[tuple[str, Clause]], decl: Declarations) -> str | None:
    if len(group) != 2 or [s for s, _ in group] != ["env_init", "sys_init"]:
        return None
    env, sys = group[0][1].formula, group[1][1].formula
    if isinstance(sys, Var) and isinstance(env, Var) and sys.name in decl.regions \
            and env.name == sys.name + REGION_COMPLETION:
        return f"Start in {sys.name}"
    return None


def _memory(group: list[tuple[str, Clause]], w: _Writer) -> str | None:
    """The four clauses of ``P is set on E and reset on F`` (see english_reader._memory)."""
    if len(group) != 4 or any(s != "sys_safety" for s, _ in group):
        return None
    first = group[0][1].formula
    if not (isinstance(first, Implies) and isinstance(first.right, Var) and isinstance(first.left, And)
            and len(first.left.args) == 2 and isinstance(first.left.args[1], Not)):
        return None
    name = first.right.name
    set_event, reset_event = first.left.args[0], first.left.args[1].arg
    return (f"{name} is set on {w.expression(set_event, 'safety', bare=True)} "
            f"and reset on {w.expression(reset_event, 'safety', bare=True)}")


def _exclusive(f: Formula) -> list[str] | None:
    """Names of an at-most-one formula (the form ``activation_completion.at_most_one`` builds)."""
    if not isinstance(f, Or) or len(f.args) < 3 or not all(isinstance(t, And) for t in f.args):
        return None
    last = f.args[-1]
    if not all(isinstance(a, Not) and isinstance(a.arg, Var) for a in last.args):
        return None
    return [a.arg.name for a in last.args]


def append_sentences(path: str | os.PathLike, sentences: Iterable[str]) -> EnglishSpec:
    """Append ``sentences`` (one per line) to the English spec at ``path``, atomically.

    The whole new text is read first; if it does not read (a sentence that does not parse, an
    unknown name) the ``SpecError`` is raised and the file is left as it was.
    """
    path = Path(path)
    try:
        old = read_text(path, "spec file")
    except InputError as e:
        raise SpecError(str(path), e.line, 0, e.message) from None
    added = [s.strip() for s in sentences if s.strip()]
    for s in added:
        if "\n" in s or "\r" in s:
            raise SpecError(str(path), 0, 0, f"a sentence is one line: {s!r}")
    text = old + ("" if not old or old.endswith("\n") else "\n") + "".join(s + "\n" for s in added)
    result = read_english(text, str(path))
    mode = path.stat().st_mode & 0o7777
    write_atomic(path, text, mode=mode)
    return result


def sentences_for(spec: Spec, clauses: Sequence[tuple[str, Clause]], decl: Declarations | None = None) -> list[str]:
    """Sentences for (section, clause) pairs added to ``spec`` — analysis suggestions, learned assumptions."""
    decl = decl or declarations_of(spec)
    w = _Writer(decl)
    return _render_group(list(clauses), w, decl) if len(clauses) > 1 else [
        clause_to_sentence(c, s, decl) for s, c in clauses]

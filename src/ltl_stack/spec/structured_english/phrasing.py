"""Formulas as the parts of Structured English sentences, for one spec's declarations: the
conditions (``you are sensing a and you were in R``), the requirements (``do a and b``) and the
goals (``visit R``), in the tense that reads back as the same state (current or next). The sentence
forms (``forms``) put these parts together; ``writer`` chooses the form.

Formulas that a sentence cannot say raise ``ValueError`` (a goal over next-state values).
"""
from __future__ import annotations

from ltl_stack.spec.activation_completion import ACTION_COMPLETION, REGION_COMPLETION
from ltl_stack.spec.formula import And, Const, Formula, Iff, Implies, Not, Or, Var, Xor, walk
from ltl_stack.spec.model import Spec
from ltl_stack.spec.ops import fold
from ltl_stack.spec.structured_english.declarations import Declarations

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


class Writer:
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

    def visited(self, f: Formula) -> str | None:
        if isinstance(f, And) and len(f.args) == 2 and all(isinstance(a, Var) and not a.primed for a in f.args):
            a, b = f.args
            for r, c in ((a, b), (b, a)):
                if r.name in self.decl.regions and c.name == r.name + REGION_COMPLETION:
                    return r.name
        return None



def split_condition(f: Formula) -> tuple[Formula | None, Formula]:
    """``a -> b`` and slugs' ``!a | b`` as (a, b); anything else as (None, f)."""
    if isinstance(f, Implies):
        return f.left, f.right
    if isinstance(f, Or) and len(f.args) >= 2 and isinstance(f.args[0], Not):
        rest = f.args[1] if len(f.args) == 2 else Or(f.args[1:])
        return f.args[0].arg, rest
    return None, f

"""Formulas as text for people: in words, as infix text and as slugsin prefix text.

The words follow the thesis' phrasing (Spec. 1 and 2, Figs. 3.7-3.8): ``not``, ``and``,
``or``, ``if … then …``, ``… if and only if …``, ``next x`` for a primed proposition, and a
section word in front: ``always`` (safety), ``infinitely often`` (liveness), ``initially`` (init)::

    always, if person then next stop_camera
    always ((not pickup and drop) or (pickup and not drop))
    infinitely often rightLane

This is text to read, not Structured English to write: the Structured English reader
(``structured_english``) has no ``next``, ``initially`` or ``where $1 = …``. Displays label it "in
words"; ``structured_english.writer`` writes sentences that read back.

Proposition names are written exactly as declared, so ``not_ready`` stays one word; a name that is
itself one of the sentence words (``and``, ``next``, …) is quoted. All renderers work bottom-up
with ``ops.fold`` (no recursion), so deep formulas are fine.

Formulas are DAGs (slugsin ``$`` buffers, integer comparisons share subformulas), and writing a
shared subformula out at every use can make the text exponentially longer than the clause. A
shared subformula longer than ``SHARE_LIMIT`` characters is therefore named: the words read
``always, if $1 then next y, where $1 = x0 and x1`` (definitions before their uses), and infix text
falls back to the slugsin prefix line with ``$`` buffers, which ``parse_structured`` reads too. The
text is built as nested parts joined once at the end, so its size and the work are linear in the
formula's size.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Tuple, Union

from ltl_stack.spec.formula import FALSE, TRUE, And, Const, Formula, Iff, Implies, Not, Or, Var, Xor, children
from ltl_stack.spec.model import SECTIONS, Clause, IntegerVariable, Spec
from ltl_stack.spec.ops import fold
from ltl_stack.spec.slugsin import formula_to_slugsin

__all__ = ["clause_in_words", "formula_in_words", "formula_to_infix", "formula_to_slugsin", "spec_in_words"]

#: a shared subformula whose text is longer than this is named (English) or written with $ buffers
SHARE_LIMIT = 40



class _Rope:
    """Text as nested parts with its length, so building a parent never copies its children."""

    __slots__ = ("parts", "size")

    def __init__(self, *parts: str | _Rope):
        self.parts = parts
        self.size = sum(len(p) if isinstance(p, str) else p.size for p in parts)

    def __len__(self) -> int:
        return self.size

    def __str__(self) -> str:
        out: list[str] = []
        stack: list[str | _Rope] = [self]
        while stack:
            item = stack.pop()
            if isinstance(item, str):
                out.append(item)
            else:
                stack.extend(reversed(item.parts))
        return "".join(out)


def _joined(separator: str, parts: Sequence[str | _Rope]) -> _Rope:
    items: list[str | _Rope] = []
    for k, part in enumerate(parts):
        if k:
            items.append(separator)
        items.append(part)
    return _Rope(*items)


def _shared(f: Formula) -> set[int]:
    """Ids of compound nodes of ``f`` with more than one parent (shared subformulas)."""
    parents: dict[int, int] = {}
    seen: set[int] = set()
    stack = [f]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        for kid in children(node):
            if not isinstance(kid, (Var, Const)):
                parents[id(kid)] = parents.get(id(kid), 0) + 1
                stack.append(kid)
    return {key for key, count in parents.items() if count > 1}


class _Names:
    """The named shared subformulas of one rendering, in the order they were defined."""

    def __init__(self, f: Formula):
        self.shared = _shared(f)
        self.definitions: list[tuple[str, str | _Rope]] = []

    def name(self, node: Formula, text: str | _Rope) -> str | None:
        """A name for ``node``'s text when it is shared and long, else None."""
        if id(node) not in self.shared or len(text) <= SHARE_LIMIT:
            return None
        name = f"${len(self.definitions) + 1}"
        self.definitions.append((name, text))
        return name

    def where(self) -> str:
        if not self.definitions:
            return ""
        return ", where " + "; ".join(f"{name} = {text}" for name, text in self.definitions)


# A rendered subformula and how it binds: "atom" needs no parentheses anywhere.
_Piece = Tuple[Union[str, _Rope], str]

_WORDS = {"not", "and", "or", "if", "then", "next", "always", "true", "false", "infinitely", "often",
          "initially", "exactly", "one", "of", "only"}

SECTION_WORDS = {
    "env_init": "initially", "sys_init": "initially",
    "env_safety": "always", "sys_safety": "always",
    "env_liveness": "infinitely often", "sys_liveness": "infinitely often",
}


def formula_to_infix(f: Formula) -> str:
    """``f`` in the structured format's infix syntax; ``parse_structured`` reads it back.

    A formula with long shared subformulas is written as its slugsin prefix line with ``$`` buffers
    (``formula_to_slugsin``) instead, which the structured reader also reads, so the text stays as
    small as the formula.
    """
    names = _Names(f)

    def combine(node: Formula, kids: tuple[_Piece, ...]) -> _Piece:
        piece = _infix_piece(node, kids)
        if names.name(node, piece[0]) is not None:
            raise _Shared
        return piece
    try:
        return str(fold(f, combine)[0])
    except _Shared:
        return formula_to_slugsin(f)


class _Shared(Exception):
    """A long shared subformula: infix text would repeat it."""


def _infix_piece(node: Formula, kids: tuple[_Piece, ...]) -> _Piece:
    if isinstance(node, Var):
        return node.name + ("'" if node.primed else ""), "atom"
    if isinstance(node, Const):
        return ("TRUE" if node.value else "FALSE"), "atom"
    if isinstance(node, Not):
        text, kind = kids[0]
        return _Rope("!", text if kind in ("atom", "not") else _Rope("(", text, ")")), "not"
    if isinstance(node, (And, Or)):
        kind = "and" if isinstance(node, And) else "or"
        if not kids:
            return ("TRUE" if kind == "and" else "FALSE"), "atom"
        if len(kids) == 1:
            return kids[0]
        parts = [t if k in ("atom", "not", kind) else _Rope("(", t, ")") for t, k in kids]
        return _joined(f" {'&' if kind == 'and' else '|'} ", parts), kind
    op, kind = {Xor: ("^", "xor"), Implies: ("->", "implies"), Iff: ("<->", "iff")}[type(node)]
    parts = [t if k in ("atom", "not") else _Rope("(", t, ")") for t, k in kids]
    return _Rope(parts[0], f" {op} ", parts[1]), kind


def _name(var: Var) -> str:
    name = f"'{var.name}'" if var.name.lower() in _WORDS else var.name
    return f"next {name}" if var.primed else name


def _integer_values(args: tuple[Formula, ...], integers: Sequence[IntegerVariable]) -> tuple[list[str], list[int]]:
    """Phrases ``x is 3`` for groups of literals in ``args`` that fix every bit of an integer.

    Returns the phrases and the positions of the literals they replace.
    """
    owner = {bit: (var, i) for var in integers for i, bit in enumerate(var.bits)}
    groups: dict[tuple[str, bool], dict[int, tuple[int, bool]]] = {}
    for position, arg in enumerate(args):
        negated = isinstance(arg, Not)
        var = arg.arg if negated else arg
        if isinstance(var, Var) and var.name in owner:
            integer, bit = owner[var.name]
            groups.setdefault((integer.name, var.primed), {})[bit] = (position, not negated)
    phrases, used = [], []
    for var in integers:
        for primed in (False, True):
            group = groups.get((var.name, primed), {})
            if var.bits and len(group) == len(var.bits):
                value = var.low + sum(1 << bit for bit, (_, on) in group.items() if on)
                phrases.append(f"{'next ' if primed else ''}{var.name} is {value}")
                used.extend(position for position, _ in group.values())
    return phrases, used


def formula_in_words(f: Formula, integers: Sequence[IntegerVariable] = ()) -> str:
    """``f`` in words (no section word in front).

    With the spec's ``integers``, a conjunction that fixes every bit of an integer reads
    ``x is 3`` (``next x is 3`` when primed) instead of listing its bits; ``and true`` and
    ``or false`` are left out. Long shared subformulas are named (``…, where $1 = …``).
    """
    names = _Names(f)
    return str(_words(f, integers, names)[0]) + names.where()


def _words(f: Formula, integers: Sequence[IntegerVariable], names: _Names) -> tuple:
    """The phrase of ``f`` and how it binds (``atom``, ``not``, ``and``, ``or``, ``if``, …)."""
    def wrap(piece: tuple, allowed: tuple[str, ...] = ("atom", "not")) -> str | _Rope:
        text, kind = piece[0], piece[1]
        return text if kind in allowed or kind == "value" else _Rope("(", text, ")")

    def condition(cause: tuple, effect: tuple) -> tuple:
        allowed = ("atom", "not", "and", "or")
        return _Rope("if ", wrap(cause, allowed), " then ", wrap(effect, allowed)), "if", None

    def combine(node: Formula, kids: tuple) -> tuple:
        piece = phrase(node, kids)
        name = names.name(node, piece[0])
        return piece if name is None else (name, "atom", None)

    # Each piece is (text, kind, piece of the negated formula for "not" pieces).
    def phrase(node: Formula, kids: tuple) -> tuple:
        if isinstance(node, Var):
            return _name(node), "atom", None
        if isinstance(node, Const):
            return ("true" if node.value else "false"), "atom", None
        if isinstance(node, Not):
            if kids[0][1] == "value":  # "x is 3" -> "x is not 3"
                return kids[0][0].replace(" is ", " is not ", 1), "atom", kids[0]
            return _Rope("not ", wrap(kids[0])), "not", kids[0]
        if isinstance(node, Or) and len(kids) >= 2 and kids[0][1] == "not":
            # slugs writes "a -> b" as "| ! a b": read it back as a condition
            rest = kids[1] if len(kids) == 2 else (
                _joined(" or ", [wrap(k, ("atom", "not", "or")) for k in kids[1:]]), "or")
            return condition(kids[0][2], rest)
        if isinstance(node, (And, Or)):
            kind = "and" if isinstance(node, And) else "or"
            if not kids:
                return ("true" if kind == "and" else "false"), "atom", None
            if len(kids) == 1:
                return kids[0]
            neutral = TRUE if kind == "and" else FALSE  # "x and true" reads as "x"
            keep = [i for i, a in enumerate(node.args) if a != neutral] or [0]
            parts = [wrap(kids[i], ("atom", "not", kind)) for i in keep]
            if kind == "and" and integers:
                phrases, used = _integer_values(tuple(node.args[i] for i in keep), integers)
                if phrases:
                    parts = phrases + [p for j, p in enumerate(parts) if j not in set(used)]
                    if len(parts) == 1:
                        return parts[0], "value", None
            if len(parts) == 1:
                return kids[keep[0]]
            return _joined(f" {kind} ", parts), kind, None
        left, right = kids
        if isinstance(node, Implies):
            return condition(left, right)
        if isinstance(node, Iff):
            return _Rope(wrap(left), " if and only if ", wrap(right)), "iff", None
        return _Rope("exactly one of ", wrap(left), " and ", wrap(right)), "xor", None
    return fold(f, combine)


def clause_in_words(clause_or_formula: Clause | Formula, section: str | None = None,
                      integers: Sequence[IntegerVariable] = ()) -> str:
    """A clause (or formula) of ``section`` (one of ``SECTIONS``) in words, the section word in front.

    Without a section only the formula is rendered, with no ``always``/``infinitely often``.
    Pass ``spec.integers`` to read integer bits as values (``x is 3``). Long shared subformulas
    are named after the sentence (``…, where $1 = …``).
    """
    f = clause_or_formula.formula if isinstance(clause_or_formula, Clause) else clause_or_formula
    if section is not None and section not in SECTION_WORDS:
        raise ValueError(f"unknown section {section!r}; expected one of {', '.join(SECTION_WORDS)}")
    names = _Names(f)
    text, kind, _ = _words(f, integers, names)
    body = str(text)
    where = names.where()
    if section is None:
        return body + where
    word = SECTION_WORDS[section]
    if kind == "if":
        return f"{word}, {body}{where}"
    if word != "infinitely often" and kind in ("and", "or", "xor", "iff"):
        return f"{word} ({body}){where}"
    return f"{word} {body}{where}"


def spec_in_words(spec: Spec) -> dict[str, list[str]]:
    """Every clause of ``spec`` in words, by section (integers read as values)."""
    return {name: [clause_in_words(c, name, spec.integers) for c in spec.section(name)] for name in SECTIONS}

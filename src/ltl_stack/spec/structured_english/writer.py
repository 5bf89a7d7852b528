"""GR(1) clauses back to Structured English sentences that the reader reads again.

``clause_to_sentence(clause, section, decl)`` writes one clause as one sentence: ``Always move``,
``If you are sensing person then do stop``, ``If C then visit R``, ``Assume always …``,
``Robot starts with …``. Reading the sentence back gives an equivalent clause in the same section
(the tense says current or next state, ``you are in R`` / ``you have finished a`` the completions).
``spec_sentences(english)`` renders a read English spec sentence by sentence, recognising the
forms that give several clauses (memory, lists of goals, ``Start in``, mutual exclusion), so the
result reads like the input. Each sentence form writes its own sentences (``forms.FORMS``:
``write_clause``, ``write_group``); this module picks the form.

Formulas that a sentence cannot say raise ``ValueError``: goals over next-state values (the
fairness clauses of [75] are generated, not written), and robot guarantees that do not constrain
anything the robot does next.
"""
from __future__ import annotations

from collections.abc import Sequence

from ltl_stack.spec.formula import Formula, Var, walk
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.structured_english.declarations import Declarations, EnglishSpec
from ltl_stack.spec.structured_english.forms import FORMS, Group
from ltl_stack.spec.structured_english.phrasing import Writer, declarations_of


def clause_to_sentence(clause: Clause | Formula, section: str, decl: Declarations | Spec) -> str:
    """One clause of ``section`` as a sentence that reads back as an equivalent clause there."""
    if isinstance(decl, Spec):
        decl = declarations_of(decl)
    f = clause.formula if isinstance(clause, Clause) else clause
    env = section.startswith("env_")
    body = _sentence_body(Writer(decl), f, section, env)
    if env and not section.endswith("_init"):
        return f"Assume {body}"
    return _capital(body)


def _sentence_body(w: Writer, f: Formula, section: str, env: bool) -> str:
    if not section.endswith(("_init", "_liveness")):
        if section not in ("env_safety", "sys_safety"):
            raise ValueError(f"unknown section {section!r}")
        robot_next = any(isinstance(v, Var) and v.primed and v.name in w.outputs for v in walk(f))
        if not env and not robot_next:
            raise ValueError("a robot guarantee that constrains nothing the robot does next cannot be written as "
                             "a sentence (it would read as an assumption)")
    for form in FORMS:
        if form.write_clause is not None:
            text = form.write_clause(w, f, section, env)
            if text is not None:
                return text
    raise ValueError(f"no sentence form writes this {section} clause")  # pragma: no cover - forms cover all


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def spec_sentences(english: EnglishSpec) -> list[str]:
    """The sentences of a read English spec rendered from its GR(1) clauses, one per input sentence.

    Clauses are grouped by the sentence they came from; forms that compile to several clauses
    (memory, visit lists, ``Start in``, mutual exclusion) are recognised and written as one
    sentence. Generated clauses (regions, completions) are left out: the declarations make them.
    """
    decl = english.declarations
    by_line: dict[int, Group] = {}
    for section in ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness"):
        for clause in english.spec.section(section):
            if clause.line in english.sentences and clause.file == english.spec.source:
                by_line.setdefault(clause.line, []).append((section, clause))
    w = Writer(decl)
    out = []
    for line in sorted(by_line):
        out.extend(_render_group(by_line[line], w))
    return out


def _render_group(group: Group, w: Writer) -> list[str]:
    """The clauses of one sentence: as one sentence when a form writes them all, else one by one."""
    for form in FORMS:
        if form.write_group is not None:
            text = form.write_group(group, w)
            if text is not None:
                return [text]
    return [clause_to_sentence(c, s, w.decl) for s, c in group]


def sentences_for(spec: Spec, clauses: Sequence[tuple[str, Clause]], decl: Declarations | None = None) -> list[str]:
    """Sentences for (section, clause) pairs added to ``spec`` — analysis suggestions, learned assumptions."""
    decl = decl or declarations_of(spec)
    w = Writer(decl)
    return _render_group(list(clauses), w) if len(clauses) > 1 else [
        clause_to_sentence(c, s, decl) for s, c in clauses]

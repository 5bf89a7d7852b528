"""The characterized spec of a Structured English spec, in English (thesis §4.7), so that
the user reads what was learned in the language the spec was written in. ROS-free.

``Characterizer`` renders phi' (Alg. 2) in the structured format, which is what is parsed and
synthesized. When the running spec is a ``.spec`` in Structured English and the user's file is a
``.spec`` too, ``english_text`` writes the user's own file back instead, with:

* every sentence that gave an environment-safety or an init clause turned into a comment
  (``# replaced by environment characterization: <sentence>``) — phi' replaces them;
* appended sentences: ``Environment starts with …`` / ``Robot starts with …`` (Alg. 2 lines 2-3),
  one ``Assume always …`` for G((/\\ psi) | disjuncts), preceded by one comment per disjunct saying
  when and what was observed, and ``Assume infinitely often …`` per user liveness (Alg. 3 line 6).

The result is read back (``read_english``) and each section compared with phi' on BDDs (one
``Game``): it is written only when it says exactly what runs. It cannot when a sentence gave
clauses of other sections too, when a disjunct has no sentence (the Structured English writer raises), or when
the clauses the declarations generate (regions, actions with completion, thesis [75]) come back as
separate assumptions that the learned disjuncts break; then ``english_text`` returns ``None`` with
the reason and the caller writes the structured format.
"""
from __future__ import annotations

import time
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.inputs import read_text
from ltl_stack.runtime.resilience.characterize import EC1, Characterizer, Observation
from ltl_stack.spec.english_files import read_english
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import And, Formula, Not, Or, Var
from ltl_stack.spec.model import SECTIONS, Spec
from ltl_stack.spec.structured_english import ENGLISH_SUFFIXES, has_section_headers
from ltl_stack.spec.structured_english.writer import clause_to_sentence
from ltl_stack.synthesis.game import Game


def is_english(path: str | Path) -> bool:
    """Does ``path`` name a Structured English spec (by its suffix)?"""
    return Path(path).suffix.lower() in ENGLISH_SUFFIXES


def _cube(values: dict[str, bool], names: list[str]) -> Formula:
    parts = [Var(n) if values[n] else Not(Var(n)) for n in names]
    return parts[0] if len(parts) == 1 else And(tuple(parts))


def english_text(ch: Characterizer, variant: str | None, observation: Observation | None,
                 target: Spec, liveness: list[tuple[str, float]]) -> tuple[str | None, str]:
    """(text, "") — the user's English with phi' — or (None, why not). ``target`` is phi' as parsed
    from the structured text (what runs); ``liveness`` the user's (text, time) pairs."""
    spec = ch.original
    if not is_english(spec.source):
        return None, f"the running spec {spec.source} is not a Structured English file"
    try:
        original = read_text(spec.source, "spec file")
    except InputError as err:
        return None, f"cannot read {spec.source} again: {err}"
    if has_section_headers(original):
        return None, f"{spec.source} is in the structured format"
    english = read_english(original, spec.source)
    decl = english.declarations
    by_line: dict[int, set[str]] = {}
    for section in SECTIONS:
        for clause in english.spec.section(section):
            if clause.line in english.sentences:
                by_line.setdefault(clause.line, set()).add(section)
    rewritten = ({"env_init", "sys_init"} if observation is not None else set()) | (
        {"env_safety"} if variant is not None else set())
    replaced = {line for line, sections in by_line.items() if sections & rewritten}
    mixed = sorted(line for line in replaced if by_line[line] - rewritten)
    if mixed:
        return None, (f"{spec.source}:{mixed[0]}: the sentence gives clauses of other sections too, so it cannot "
                      "be replaced by the characterized ones alone")
    added: list[str] = ["", "# ---- learned by environment characterization (thesis §4.7, Alg. 2"
                        + (f"; variant {variant}" if variant else "") + ") ----"]
    try:
        if observation is not None:
            added += [f"# Alg. 2 line 2: the incoming inputs observed at step {observation.step}",
                      clause_to_sentence(_cube(observation.incoming, spec.inputs), "env_init", decl),
                      f"# Alg. 2 line 3: the current outputs observed at step {observation.step}",
                      clause_to_sentence(_cube(observation.current_outputs, spec.outputs), "sys_init", decl)]
        if variant is not None:
            disjuncts = ch.ec1 if variant == EC1 else ch.ec2
            added.append(f"# G((the original assumptions) | {variant} disjuncts), Alg. 2 line "
                         f"{6 if variant == EC1 else 9}; the original assumptions are the sentences marked "
                         "'replaced' above")
            for k, d in enumerate(disjuncts, 1):
                added.append(f"# disjunct {k}: {d.comment()}")
            psi = [c.formula for c in spec.env_safety]
            parts = ([psi[0] if len(psi) == 1 else And(tuple(psi))] if psi else []) + \
                [d.formula for d in disjuncts]
            added.append(clause_to_sentence(parts[0] if len(parts) == 1 else Or(tuple(parts)), "env_safety", decl))
        for text, when in liveness:
            added.append(f"# added by the user {time.strftime('%Y-%m-%d %H:%M:%S', time.localtime(when))} "
                         f"(Alg. 3 line 6): {text}")
            added.append(clause_to_sentence(ch.check_liveness(text), "env_liveness", decl))
    except ValueError as err:
        return None, f"a learned formula has no Structured English sentence: {err}"
    lines = original.splitlines()
    out = [f"# Specification rewritten at runtime by ltl_stack's environment characterization from {spec.source}.",
           "# It loads like any spec: synthesize FILE, controller_executor FILE."]
    for number, line in enumerate(lines, start=1):
        out.append(f"# replaced by environment characterization: {line}" if number in replaced else line)
    text = "\n".join(out + added) + "\n"
    try:
        reread = read_english(text, str(ch.path) if ch.path is not None else spec.source).spec
    except SpecError as err:
        return None, f"the English text does not read back: {err}"
    problem = _differs(reread, target)
    if problem:
        return None, problem
    return text, ""


def _differs(english: Spec, target: Spec) -> str:
    """"" when both specs say the same (same propositions, each section equivalent), else what differs."""
    if list(english.inputs) != list(target.inputs) or list(english.outputs) != list(target.outputs):
        return "the English text declares other propositions"
    game = Game(target)
    bdd = game.bdd
    for section in SECTIONS:
        mine = [game.to_bdd(c.formula) for c in english.section(section)]
        theirs = [game.to_bdd(c.formula) for c in target.section(section)]
        if section.endswith("liveness"):  # each goal on its own: compare the sets
            same = set(mine) == set(theirs)
        else:
            same = _conjoin(bdd, mine) == _conjoin(bdd, theirs)
        if not same:
            return (f"read back, the English text's {section} differs from the characterized spec (the clauses "
                    "its declarations generate come back as separate assumptions)")
    return ""


def _conjoin(bdd, parts: list) -> object:
    result = bdd.true
    for u in parts:
        result &= u
    return result


__all__ = ["english_text", "is_english"]

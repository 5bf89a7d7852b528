"""A Structured English file read into the GR(1) ``Spec``: its lines split into declarations and
sentences, each sentence compiled by the first form of ``forms.FORMS`` that recognizes it (after
``Assume``, and once per member of a group for ``visit all rooms``), each clause keeping the
sentence's text, file and line; a mistake is one ``SpecError`` with the closest sentence that reads
as a hint.

Each line is read once, and the condition reader is iterative: time and memory are linear in the
size of the file, and nesting depth costs no stack.
"""
from __future__ import annotations

import difflib
import re
from pathlib import Path

from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import Formula
from ltl_stack.spec.model import SECTIONS, Clause, Spec
from ltl_stack.spec.structured_english.declarations import (
    DECLARATION,
    Declarations,
    EnglishSpec,
    add_conventions,
    declare,
)
from ltl_stack.spec.structured_english.forms import VOCABULARY, Reading, read_form
from ltl_stack.spec.structured_english.sentence import Sentence
from ltl_stack.spec.structured_english.vocabulary import KEYWORDS, Token

ENGLISH_SUFFIXES = (".spec", ".english")
#: sentences ``all G`` / ``each G`` may make in one spec, one per member (100 sentences ``visit all G``
#: over a group of 2,000 regions made 200,000 goals: minutes before synthesis printed anything)
MAX_REPEATED = 10_000

_COMMENT = re.compile(r"(^|\s)#")


def has_section_headers(text: str) -> bool:
    """Does the first line that is not blank or a comment start with '[' (a slugs-format file)?"""
    for raw in text.splitlines():
        m = _COMMENT.search(raw)
        body = (raw[:m.start()] if m else raw).strip()
        if body:
            return body.startswith("[")
    return False


def read_sentences(text: str, file: str, base_dir: Path) -> EnglishSpec:
    """A plain Structured English file (declarations, then sentences): its spec, declarations and
    sentences. ``english_files.read_english`` is the entry that also takes LTLMoP project files."""
    lines = []
    for number, raw in enumerate(text.splitlines(), start=1):
        m = _COMMENT.search(raw)
        body = (raw[:m.start()] if m else raw).rstrip()
        if body.strip():
            lines.append((number, body))
    decl = Declarations()
    sentences: list[tuple[int, str]] = []
    for number, body in lines:
        m = DECLARATION.match(body)
        if m:
            declare(decl, m, number, body, file, Path(base_dir))
        else:
            sentences.append((number, body))
    return compile_sentences(decl, sentences, file)


def is_ltlmop_project(text: str) -> bool:
    """Is ``text`` an LTLMoP project file (its ``======== SETTINGS ========`` container)?"""
    return re.search(r"^=+ *(SETTINGS|SPECIFICATION) *=+\s*$", text, re.MULTILINE) is not None


def compile_sentences(decl: Declarations, sentences: list[tuple[int, str]], file: str,
                      clauses: dict[str, list[Clause]] | None = None) -> EnglishSpec:
    """The spec of ``sentences`` (line, text) over ``decl`` (after ``clauses`` already read, by
    section), with the generated conventions."""
    sections: dict[str, list[Clause]] = {name: list((clauses or {}).get(name, [])) for name in SECTIONS}
    for number, body in sentences:
        for section, formula in compile_sentence(Sentence(body, number, file, decl)):
            sections[section].append(Clause(formula, body.strip(), file, number))
    add_conventions(decl, sections, file)
    spec = Spec(inputs=decl.inputs, outputs=decl.outputs, source=file, **sections)
    if decl.topology is not None:
        spec.warnings.extend(decl.topology.warnings)
    return EnglishSpec(spec, decl, dict(sentences))


def compile_sentence(s: Sentence, hints: bool = True) -> list[tuple[str, Formula]]:
    """The (section, formula) clauses of one sentence; with ``hints``, an error about the shape of
    the sentence suggests the closest sentence that reads."""
    try:
        return _quantified(s)
    except SpecError as e:
        hint = _closest_form(s, e) if hints and getattr(e, "form", False) else None
        if hint and "did you mean" not in e.message:
            raise SpecError(e.file, e.line, e.column, f"{e.message}; did you mean '{hint}'?") from None
        raise


def _quantified(s: Sentence) -> list[tuple[str, Formula]]:
    """``all X`` / ``each X`` / ``any X`` over a group (one per sentence, as in LTLMoP's
    ``parseEnglishToLTL``): in a condition, a memory or toggle event or a start, ``all`` is the
    members' conjunction and ``any`` their disjunction; elsewhere ``any`` is the disjunction
    and ``all``/``each`` repeat the sentence once per member (``visit all rooms``)."""
    toks = s.tokens
    s.refuse_unsupported(toks)
    at = next((i for i, t in enumerate(toks[:-1]) if t.low in ("all", "any", "each")
               and toks[i + 1].text in s.decl.groups and t.text not in s.decl.kind_of), None)
    if at is None:
        loose = next((t for i, t in enumerate(toks[:-1]) if t.low in ("all", "any", "each")
                      and toks[i + 1].kind == "word" and toks[i + 1].text not in s.decl.kind_of
                      and toks[i + 1].low not in KEYWORDS and t.text not in s.decl.kind_of), None)
        if loose is not None:
            name = toks[toks.index(loose) + 1]
            groups = ", ".join(s.decl.groups) or "none defined"
            raise s.error(name.column, f"unknown group '{name.text}' after '{loose.text}' (define it first: "
                                       f"'group {name.text} is <region>, <region>'; groups: {groups})")
        return _compile(s, toks)
    members = s.decl.groups[toks[at + 1].text]
    column = toks[at].column
    if toks[at].low == "any" or _in_condition(s, toks, at):
        joiner = "or" if toks[at].low == "any" else "and"
        group: list[Token] = [Token("(", "(", column)]
        for k, member in enumerate(members):
            if k:
                group.append(Token("word", joiner, column))
            group.append(Token("word", member, column))
        group = group + [Token(")", ")", column)] if members else [Token("word", "false", column)]
        return _compile(s, toks[:at] + group + toks[at + 2:])
    out: list[tuple[str, Formula]] = []
    s.decl.repeated += len(members)
    if s.decl.repeated > MAX_REPEATED:
        raise s.error(column, f"'{toks[at].text} {toks[at + 1].text}' repeats this sentence for each of "
                              f"{len(members)} members: with the sentences before it, more than "
                              f"{MAX_REPEATED:,} (the most a spec may make this way; a goal per member "
                              "makes synthesis slow long before)")
    for member in members:
        out.extend(_compile(s, toks[:at] + [Token("word", member, column)] + toks[at + 2:]))
    return out


def _in_condition(s: Sentence, toks: list[Token], at: int) -> bool:
    """Is token ``at`` part of a condition (or an event, a start) rather than a requirement?"""
    words = [t.low for t in toks]
    start = 1 if words[:1] in (["always"], ["assume"]) else 0
    if words[start:start + 1] == ["if"]:
        then = s.find(toks, ("then",))
        return then is not None and at < then
    iff = s.find(toks, ("if", "and", "only", "if"))
    if iff is not None:
        return at > iff
    unless = s.find(toks, ("unless",))
    if unless is not None:
        return at > unless
    return "set" in words or "toggled" in words or "start" in words or "starts" in words


def _compile(s: Sentence, toks: list[Token]) -> list[tuple[str, Formula]]:
    """The clauses of the sentence ``toks``: ``Assume`` (an assumption), then its form."""
    words = [t.low for t in toks]
    forced = None
    start = 0
    if words[:1] == ["assume"]:
        forced, start = "env", 1
        if len(toks) == 1:
            raise s.error(toks[0].column + 6, "expected a sentence after 'Assume'")
        if toks[1].kind == ",":
            start = 2
    rest = toks[start:]
    if not rest:
        raise s.error(1, "expected a sentence")
    s.refuse_unsupported(rest)
    return read_form(Reading(s, rest, words[start:], forced, False))


def _closest_form(s: Sentence, error: SpecError) -> str | None:
    """The user's sentence with one word changed (a misspelt keyword or name) or one sentence word
    inserted next to where the error is, if that reads; None otherwise. A hint never rewrites the
    sentence into another form, so it cannot change what the user said."""
    toks = s.tokens
    if not toks or len(toks) > 60:
        return None
    known = [*VOCABULARY, *s.decl.kind_of, *s.decl.groups]
    body = s.body
    tries: list[str] = []
    for t in toks:
        if t.kind == "word" and t.low not in VOCABULARY and t.text not in s.decl.kind_of \
                and t.text not in s.decl.groups:
            for word in difflib.get_close_matches(t.low if t.low in known else t.text, known, n=3, cutoff=0.75):
                tries.append(body[:t.column - 1] + word + body[t.column - 1 + len(t.text):])
    at = max((k for k, t in enumerate(toks) if t.column <= error.column), default=0)
    for k in sorted(range(len(toks) + 1), key=lambda k: abs(k - at)):
        column = toks[k].column if k < len(toks) else len(body.rstrip()) + 2
        for word in ("are", "then", "to", "is", "on", "of"):  # words that only complete a form
            tries.append((body[:column - 1] + word + " " + body[column - 1:]).rstrip())
    for text in tries:
        try:
            compile_sentence(Sentence(text, s.line, s.file, s.decl), hints=False)
        except SpecError:
            continue
        return text.strip()
    return None

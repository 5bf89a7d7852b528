"""Structured English (LTLMoP's sentences, [46]): tasks read into the GR(1) ``Spec`` and clauses
written back as sentences that read again.

A file has declarations (``Keyword: names``) and one sentence per line, as in the thesis::

    Sensors: person
    Actions: move, stop
    Always move.
    If you are sensing person then do stop.

Declarations: ``Sensors:`` (environment inputs), ``Actions:`` (robot outputs that act at once),
``Actions with completion:`` (the robot activates ``a``, the environment reports ``a_ac``),
``Memory:`` (robot propositions kept by ``is set on … and reset on …``), ``Regions:`` (names;
every region touches every other) or ``Map:`` (an LTLMoP ``.regions`` file, relative to the spec,
whose adjacency becomes the topology). Regions get ``R`` (head for R) and ``R_rc`` (in R).
``Other robots:`` is reserved for the negotiation of several robots.

Sentences compile with the activation–completion encoding of [75] (``activation_completion``);
each clause keeps the sentence's text, file and line. The full grammar and what each sentence
compiles to are in ``docs/spec_formats.md`` (section "Structured English").

The modules, each with one job:

- ``vocabulary``: reserved words, tokens, phrases (``you are sensing`` …);
- ``declarations``: the declaration lines and the clauses their conventions generate;
- ``sentence``: one sentence line, the condition reader and the pieces the forms share;
- ``forms``: the table of sentence forms (recognizer, builder, templates, writer counterpart);
- ``reader``: a file into a spec (``read_sentences``, ``compile_sentences``);
- ``phrasing`` and ``writer``: clauses back to sentences (``clause_to_sentence``, ``spec_sentences``).

LTLMoP project files (``======== SETTINGS ========`` …) are read by ``spec.ltlmop_project`` into the
same ``Declarations`` and sentences; ``spec.english_files.read_english`` takes either kind of file.
"""
from __future__ import annotations

from ltl_stack.spec.structured_english.declarations import (
    DECLARATION_KINDS,
    Declarations,
    EnglishSpec,
    add_declaration,
)
from ltl_stack.spec.structured_english.forms import FORMS, TEMPLATES, VOCABULARY, SentenceForm
from ltl_stack.spec.structured_english.reader import (
    ENGLISH_SUFFIXES,
    MAX_REPEATED,
    compile_sentences,
    has_section_headers,
    is_ltlmop_project,
    read_sentences,
)
from ltl_stack.spec.structured_english.vocabulary import KEYWORDS, PHRASES, UNSUPPORTED

__all__ = [
    "DECLARATION_KINDS", "ENGLISH_SUFFIXES", "FORMS", "KEYWORDS", "MAX_REPEATED", "PHRASES", "TEMPLATES",
    "UNSUPPORTED", "VOCABULARY", "Declarations", "EnglishSpec", "SentenceForm", "add_declaration",
    "compile_sentences", "has_section_headers", "is_ltlmop_project", "read_sentences",
]

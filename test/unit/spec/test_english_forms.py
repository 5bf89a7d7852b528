"""The table of Structured English sentence forms (``structured_english.forms.FORMS``): each form's
templates are sentences of that form (the first form that recognizes them is the form itself), they
read, and a form that writes sentences writes ones that the same form reads back."""
from __future__ import annotations

from pathlib import Path

import pytest

from ltl_stack.spec.english_files import read_english
from ltl_stack.spec.structured_english import FORMS, TEMPLATES, VOCABULARY, read_sentences
from ltl_stack.spec.structured_english.forms import Reading
from ltl_stack.spec.structured_english.sentence import Sentence
from ltl_stack.spec.structured_english.writer import spec_sentences

HEADER = ("Sensors: person\nActions: move, stop\nActions with completion: pick\nMemory: seen\n"
          "Regions: r1, r2\n")
NAMES = {"<p>": "move", "<action>": "stop", "<sensor>": "person", "<region>": "r1", "<memory>": "seen"}


def _sentence(template: str) -> str:
    template = template.replace("finished <action>", "finished pick")  # an action with completion
    if template.startswith("assume"):  # an assumption speaks of what the robot senses
        template = template.replace("<p>", "person")
    for placeholder, name in NAMES.items():
        template = template.replace(placeholder, name, 1).replace(placeholder, "move" if name != "move" else "stop")
    return template


def _form_of(text: str) -> str:
    """The name of the form that reads ``text`` (after ``Assume``, as the reader strips it)."""
    english = read_sentences(HEADER, "forms.spec", Path("."))
    s = Sentence(text, 1, "forms.spec", english.declarations)
    toks = s.tokens[1:] if s.tokens[0].low == "assume" else s.tokens
    r = Reading(s, toks, [t.low for t in toks], "env" if toks is not s.tokens else None, False)
    return next(form.name for form in FORMS if form.recognize(r))


@pytest.mark.parametrize(("form", "template"), [(f.name, t) for f in FORMS for t in f.templates])
def test_each_template_is_read_by_its_own_form(form, template):
    text = _sentence(template)
    assert _form_of(text) == form, text
    spec = read_english(HEADER + text + "\n", "forms.spec").spec
    assert any(c.line == 6 for s in ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness",
                                     "sys_liveness") for c in spec.section(s)), text


def test_the_templates_list_every_form_that_has_templates_in_table_order():
    assert TEMPLATES == [t for f in FORMS for t in f.templates]
    assert len(TEMPLATES) == len(set(TEMPLATES))


def test_a_form_is_listed_before_the_forms_that_would_also_read_its_sentences():
    """``visit r1 and stay there`` is its own form, not a ``visit`` list; ``always if …`` is ``always``."""
    assert _form_of("visit r1 and stay there") == "visit and stay"
    assert _form_of("always if you are sensing person then do stop") == "always"
    assert _form_of("do stop if and only if you are sensing person") == "if and only if"
    assert _form_of("stop") == "safety"


def test_every_form_word_is_one_a_hint_may_use():
    assert all(w in VOCABULARY for f in FORMS for w in f.words)


@pytest.mark.parametrize("text", ["Start in r1", "seen is set on person and reset on finished pick",
                                  "move and stop are mutually exclusive", "Visit r1 and r2",
                                  "If you are sensing person then do stop", "Always move"])
def test_a_form_that_writes_back_writes_a_sentence_of_the_same_form(text):
    english = read_english(HEADER + text + "\n", "forms.spec")
    (written,) = spec_sentences(english)
    assert _form_of(written) == _form_of(text), written

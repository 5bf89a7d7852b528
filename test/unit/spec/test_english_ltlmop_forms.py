"""Structured English II: LTLMoP's timing and the sentence forms of its structured parser.

Each expected formula is what LTLMoP's ``parseEnglishToLTL`` makes of the sentence (read for the
facts: which names it wraps in next()), written in the structured format's infix."""
from __future__ import annotations

import pytest
from english_testing import Bdds
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.spec.english_files import parse_english, read_english
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.structured import parse_structured
from ltl_stack.synthesis import is_realizable

DECLARATIONS = """\
Sensors: person, door
Actions: move, stop
Actions with completion: pick
Memory: seen, flag
Regions: r1, r2, r3
"""
NAMES = ["person", "door", "pick_ac", "r1_rc", "r2_rc", "r3_rc", "move", "stop", "pick", "seen", "flag", "r1", "r2",
         "r3"]
SIGNATURE = "[INPUT]\nperson\ndoor\npick_ac\nr1_rc\nr2_rc\nr3_rc\n[OUTPUT]\nmove\nstop\npick\nseen\nflag\nr1\nr2\nr3\n"


def equivalent(a, b) -> bool:
    bdds = Bdds(NAMES)
    return bdds.of(a) == bdds.of(b)


def _clauses(sentence: str, section: str) -> list:
    spec = parse_english(DECLARATIONS + sentence + "\n", "t.spec")
    return [c.formula for c in spec.section(section) if c.line == 6]


def _expected(section: str, infix: list[str]) -> list:
    header = {"sys_safety": "SYS_TRANS", "env_safety": "ENV_TRANS", "sys_liveness": "SYS_LIVENESS",
              "sys_init": "SYS_INIT"}[section]
    spec = parse_structured(SIGNATURE + f"[{header}]\n" + "\n".join(infix) + "\n", "e.ltl")
    return [c.formula for c in spec.section(section)]


STAY = "(r1_rc | !r1') & (r2_rc | !r2') & (r3_rc | !r3')"

FORMS = [
    # memory (parseEvent): what the environment reports at the next step, the robot's own values now
    ("seen is set on person and reset on stop", "sys_safety",
     ["(person' & !stop) -> seen'", "stop -> !seen'", "(seen & !stop) -> seen'", "(!seen & !person') -> !seen'"]),
    ("seen is set on move and not seen and reset on move and seen", "sys_safety",
     ["((move & !seen) & !(move & seen)) -> seen'", "(move & seen) -> !seen'", "(seen & !(move & seen)) -> seen'",
      "(!seen & !(move & !seen)) -> !seen'"]),
    ("seen is set on finished pick and reset on false", "sys_safety",
     ["(pick_ac' & !FALSE) -> seen'", "FALSE -> !seen'", "(seen & !FALSE) -> seen'", "(!seen & !pick_ac') -> !seen'"]),
    ("seen is set on you had finished pick and reset on false", "sys_safety",  # the thesis' compiled reading
     ["(pick_ac & !FALSE) -> seen'", "FALSE -> !seen'", "(seen & !FALSE) -> seen'", "(!seen & !pick_ac) -> !seen'"]),
    # conditions (parseCond): a name without a phrase is read now, a present-tense phrase next
    ("if seen then do stop", "sys_safety", ["seen -> stop'"]),
    ("do move if and only if seen and not flag", "sys_safety", ["move' <-> (seen & !flag)"]),
    ("if you are activating seen then do stop", "sys_safety", ["seen' -> stop'"]),
    # edges
    ("if start of person then do stop", "sys_safety", ["(!person & person') -> stop'"]),
    ("do stop if and only if end of seen and you are not activating flag", "sys_safety",
     ["stop' <-> ((seen & !seen') & !flag')"]),
    ("if you were activating start of seen then stay there", "sys_safety", [f"(!seen & seen') -> ({STAY})"]),
    ("do stop if and only if you were not activating seen and end of flag", "sys_safety",  # an edge ends a phrase
     ["stop' <-> (!seen & (flag & !flag'))"]),
    # stay there
    ("if you are activating stop then stay there", "sys_safety", [f"stop' -> ({STAY})"]),
    ("go to r2 and stay there", "sys_liveness", ["r2 & r2_rc"]),
    ("go to r2 and stay there", "sys_safety", [f"(r2 & r2_rc) -> ({STAY})"]),
    ("if you are activating seen then go to r2 and stay there", "sys_safety", [f"seen -> ((r2 & r2_rc) -> ({STAY}))"]),
    # if C then always P
    ("If you did not activate seen then always not r1", "sys_safety", ["!seen -> !r1'"]),
    ("if you are sensing person then always not move", "sys_safety", ["person' -> !move'"]),
    # toggle (parseToggle: the event is a condition)
    ("flag is toggled on person", "sys_safety",
     ["(flag & person) -> !flag'", "(!flag & person) -> flag'", "(flag & !person) -> flag'",
      "(!flag & !person) -> !flag'"]),
    ("flag is toggled when end of seen", "sys_safety",
     ["(flag & (seen & !seen')) -> !flag'", "(!flag & (seen & !seen')) -> flag'",
      "(flag & !(seen & !seen')) -> flag'", "(!flag & !(seen & !seen')) -> !flag'"]),
    # an assumption: the robot's values are read now
    ("if you are in r1 then do not person", "env_safety", ["r1_rc' -> !person'"]),
    ("if you are activating move then do not person", "env_safety", ["move -> !person'"]),
]


@pytest.mark.parametrize("sentence, section, expected", FORMS)
def test_sentence_form_means_what_ltlmop_makes_of_it(sentence, section, expected):
    got = _clauses(sentence, section)
    want = _expected(section, expected)
    assert len(got) == len(want)
    for g, w in zip(got, want):
        assert equivalent(g, w), (sentence, g)


GROUPS = DECLARATIONS + "group rooms is r1, r3\n"


def test_groups_all_any_each():
    spec = parse_english(GROUPS + "visit all rooms\ngo to any room\nif you are in all rooms then do stop\n"
                         "if you are in any rooms then do move\nif you are not activating seen then visit each rooms\n"
                         "robot starts in any rooms\n", "g.spec")
    goals = {c.line: [] for c in spec.sys_liveness}
    for c in spec.sys_liveness:
        goals[c.line].append(c.formula)
    want = _expected("sys_liveness", ["r1 & r1_rc", "r3 & r3_rc", "(r1 & r1_rc) | (r3 & r3_rc)",
                                      "!seen -> (r1 & r1_rc)", "!seen -> (r3 & r3_rc)"])
    assert [len(goals[k]) for k in (7, 8, 11)] == [2, 1, 2]
    for g, w in zip(goals[7] + goals[8] + goals[11], want):
        assert equivalent(g, w)
    safety = {c.line: c.formula for c in spec.sys_safety if c.line in (9, 10)}
    assert equivalent(safety[9], _expected("sys_safety", ["(r1_rc' & r3_rc') -> stop'"])[0])
    assert equivalent(safety[10], _expected("sys_safety", ["(r1_rc' | r3_rc') -> move'"])[0])
    init = [c.formula for c in spec.sys_init if c.line == 12]
    assert equivalent(init[0], _expected("sys_init", ["r1 | r3"])[0])


def test_quantifier_over_an_undefined_group_is_a_name_error():
    with pytest.raises(SpecError, match="unknown group 'rooms' after 'all'"):
        parse_english(DECLARATIONS + "visit all rooms\n", "g.spec")


@pytest.mark.parametrize("sentence, construct", [
    ("always not between r1 and r2", "'between R1 and R2'"),
    ("always not within 40 of r1", "'within N of R'"),
    ("if you are sensing person then visit r1 at least once", "'at least once'"),
    ("after each time you are sensing person, visit r1", "'after each time'"),
])
def test_unsupported_constructs_are_named(sentence, construct):
    with pytest.raises(SpecError) as caught:
        parse_english(DECLARATIONS + sentence + "\n", "u.spec")
    assert f"{construct} (" in caught.value.message and "is not supported" in caught.value.message
    assert "unknown proposition" not in caught.value.message


def test_the_ltlmop_toggle_idiom_is_realizable():
    """A set/reset memory over its own value (LTLMoP's linefollower idiom): with every name read at the
    next step the two events contradict each other whenever the sensor fires (unrealizable before)."""
    text = ("Sensors: touch\nActions: halt\nMemory: stopped\n"
            "stopped is set on touch and not stopped and reset on touch and stopped\n"
            "if stopped then do halt\ninfinitely often touch\n")
    assert is_realizable(parse_english(text, "toggle.spec"))


# -- hints never change meaning --------------------------------------------------------------

SENTENCES = [
    "if you are sensing person then do stop",
    "do move if and only if you are sensing door and you are not activating seen",
    "If you did not activate seen then always not r1",
    "seen is set on person and reset on finished pick",
    "if you are activating stop then stay there",
    "visit r1, r2 and r3",
    "do stop unless you are sensing person",
    "if you were in r1 then do not move",
]


def _misspell(word: str, k: int, kind: int) -> str:
    k %= len(word)
    if kind == 0:
        return word[:k] + word[k + 1:] if len(word) > 1 else word + "x"
    if kind == 1:
        return word[:k] + "q" + word[k:]
    return word[:k] + word[k + 1:k + 2] + word[k:k + 1] + word[k + 2:] if k + 1 < len(word) else word + "z"


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(SENTENCES), st.integers(0, 40), st.integers(0, 40), st.integers(0, 2))
def test_a_hint_differs_only_in_the_misspelt_word_and_reads_as_meant(sentence, position, k, kind):
    words = sentence.split(" ")
    i = position % len(words)
    bad = _misspell(words[i], k, kind)
    if bad.lower() == words[i].lower():
        return
    typo = " ".join(words[:i] + [bad] + words[i + 1:])
    try:
        parse_english(DECLARATIONS + typo + "\n", "h.spec")
        return  # the misspelling happens to read (another name or word): nothing to suggest
    except SpecError as e:
        message = e.message
    if "did you mean '" not in message:
        return
    hint = message.split("did you mean '", 1)[1].rsplit("'?", 1)[0]
    if " " not in hint:  # a name: 'persn' -> 'person'
        assert hint in DECLARATIONS
        return
    hint_words, typo_words = hint.split(" "), typo.split(" ")
    assert len(hint_words) in (len(typo_words), len(typo_words) + 1)
    if len(hint_words) == len(typo_words):
        changed = [j for j, (a, b) in enumerate(zip(hint_words, typo_words)) if a != b]
        assert changed == [i], (typo, hint)
    hinted = read_english(DECLARATIONS + hint + "\n", "h.spec").spec
    if hint_words == words:  # the hint restores the user's word: the same formulas
        meant = read_english(DECLARATIONS + sentence + "\n", "h.spec").spec
        for section in ("sys_safety", "env_safety", "sys_liveness"):
            assert len(hinted.section(section)) == len(meant.section(section))
            for a, b in zip(hinted.section(section), meant.section(section)):
                assert equivalent(a.formula, b.formula)


def test_the_hint_of_issue_24_no_longer_inverts_the_meaning():
    text = DECLARATIONS + "If you did not activat seen then always not r1\n"
    with pytest.raises(SpecError) as caught:
        parse_english(text, "h.spec")
    assert caught.value.message.endswith("did you mean 'If you did not activate seen then always not r1'?")

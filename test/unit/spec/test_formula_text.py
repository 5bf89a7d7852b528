"""Formulas in words and as infix text (``spec.formula_text``)."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from spec_testing import NAMES, SPECS, formulas

from ltl_stack.spec import load_spec, parse_slugsin, parse_structured
from ltl_stack.spec.formula import FALSE, TRUE, And, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.formula_text import (
    clause_in_words,
    formula_in_words,
    formula_to_infix,
    formula_to_slugsin,
    spec_in_words,
)
from ltl_stack.spec.model import Clause
from ltl_stack.spec.ops import evaluate_many, flatten


def v(name: str, primed: bool = False) -> Var:
    return Var(name, primed)


@pytest.mark.parametrize("f, section, expected", [
    (Implies(v("person"), v("stop_camera", True)), "sys_safety", "always, if person then next stop_camera"),
    (Or((Not(v("person", True)), v("stop_camera", True))), "sys_safety",
     "always, if next person then next stop_camera"),
    (v("rightLane"), "sys_liveness", "infinitely often rightLane"),
    (Or((And((Not(v("pickup")), v("drop"))), And((v("pickup"), Not(v("drop")))),
         And((Not(v("pickup")), Not(v("drop")))))), "sys_safety",
     "always ((not pickup and drop) or (pickup and not drop) or (not pickup and not drop))"),
    (And((v("drop"), v("finished_drop"))), "sys_liveness", "infinitely often drop and finished_drop"),
    (Not(v("move")), "sys_init", "initially not move"),
    (Iff(v("pickup", True), And((v("object"), Not(v("holdingObject"))))), "sys_safety",
     "always (next pickup if and only if (object and not holdingObject))"),
    (Or((Not(Not(v("sense"))), v("move"), v("stop"))), "env_safety", "always, if not sense then move or stop"),
    (Xor(v("a"), Or((v("b"), v("c")))), None, "exactly one of a and (b or c)"),
    (Implies(Implies(v("a"), v("b")), v("c")), None, "if (if a then b) then c"),
    (And((TRUE, Not(FALSE))), None, "not false"),  # "and true" is left out
    (Or((FALSE, TRUE)), None, "true"),
])
def test_structured_english_sentences(f, section, expected):
    got = clause_in_words(Clause(f), section)
    assert got == expected, got


def test_names_are_kept_intact():
    f = And((Not(v("not_ready")), v("next_to_door", True), v("and"), Or((v("or_gate"), v("If")))))
    got = formula_in_words(f)
    assert got == "not not_ready and next next_to_door and 'and' and (or_gate or 'If')", got


def test_unknown_section_is_refused():
    with pytest.raises(ValueError, match="unknown section 'sys_goals'"):
        clause_in_words(v("a"), "sys_goals")


def test_thesis_example_reads_as_sentences():
    path = SPECS / "simple" / "simple.slugsin"
    if not path.is_file():
        pytest.skip(f"shared spec {path} is absent")
    spec = load_spec(path)
    got = [clause_in_words(c, "sys_safety") for c in spec.sys_safety]
    assert got == ["always, if next person then next stop_camera",
                   "always, if not next sense_object then next move",
                   "always, if next sense_object then next stop"], got


def test_renderers_handle_very_deep_formulas():
    f = v("a")
    for i in range(5000):
        f = Not(f) if i % 2 else Xor(f, v("b"))
    assert formula_in_words(f).count("exactly one of") == 2500
    assert formula_to_infix(f).count("^") == 2500
    assert formula_to_slugsin(f).count("^") == 2500


@pytest.mark.parametrize("f, expected", [
    (Implies(And((v("a"), v("b"))), Or((v("c", True), Not(v("a"))))), "(a & b) -> (c' | !a)"),
    (Not(Iff(v("a"), Xor(v("b"), v("c")))), "!(a <-> (b ^ c))"),
    (And(()), "TRUE"),
    (Or(()), "FALSE"),
    (Not(Not(v("x@1", True))), "!!x@1'"),
])
def test_infix_text(f, expected):
    assert formula_to_infix(f) == expected, formula_to_infix(f)


@settings(max_examples=300, deadline=None)
@given(formulas())
def test_infix_parses_back_to_the_same_formula(f):
    header = "[INPUT]\n" + "\n".join(NAMES) + "\n[OUTPUT]\n[SYS_TRANS]\n"
    spec = parse_structured(header + formula_to_infix(f) + "\n")
    assert spec.sys_safety[0].formula == flatten(f), (formula_to_infix(f), f)


def test_integers_read_as_values():
    spec = parse_structured("[INPUT]\nx:0...5\n[OUTPUT]\ndone\n[SYS_INIT]\nx = 4\n[SYS_TRANS]\n"
                            "x' != 3 | done'\n[SYS_LIVENESS]\nx' = 0 & done\n", "i.ltl")
    got = spec_in_words(spec)
    assert got["sys_init"] == ["initially x is 4"], got
    assert got["sys_safety"] == ["always (next x is not 3 or next done)"], got
    assert got["sys_liveness"] == ["infinitely often next x is 0 and done"], got
    assert got["env_init"] == ["initially not (x@2 and x@1)"], got  # the range constraint 0<=x<=5
    # without the integers the bits show
    assert clause_in_words(spec.sys_init[0], "sys_init") == "initially (not x@0.0.5 and not x@1 and x@2)"


def doubling_clause(levels: int) -> str:
    """A slugsin clause whose buffer entries each use the previous one twice: as a tree it has
    about 2^levels nodes, as written a few tokens per level."""
    entries = ["| a' b"] + [f"^ ? {k} ! ? {k}" if k % 2 else f"& ? {k} | b ? {k}" for k in range(levels - 1)]
    return f"$ {levels} " + " ".join(entries)


def test_shared_subformulas_are_named_and_the_text_stays_linear():
    line = doubling_clause(60)
    spec = parse_slugsin(f"[INPUT]\na\nb\n[OUTPUT]\n[SYS_TRANS]\n{line}\n", "shared.slugsin")
    clause = spec.sys_safety[0]
    english = clause_in_words(clause, "sys_safety")
    infix = formula_to_infix(clause.formula)
    assert len(english) <= 20 * len(line) and len(infix) <= 20 * len(line), (len(english), len(infix))
    assert ", where $1 = " in english, english[:200]
    # every name is defined once, before the definitions that use it
    definitions = english.split(", where ", 1)[1].split("; ")
    for k, definition in enumerate(definitions, start=1):
        name, body = definition.split(" = ", 1)
        assert name == f"${k}" and f"${k + 1} " not in body + " ", definition


def test_infix_of_a_shared_formula_reads_back_to_the_same_meaning():
    line = doubling_clause(12)
    spec = parse_slugsin(f"[INPUT]\na\nb\n[OUTPUT]\n[SYS_TRANS]\n{line}\n", "shared.slugsin")
    f = spec.sys_safety[0].formula
    again = parse_structured(f"[INPUT]\na\nb\n[OUTPUT]\n[SYS_TRANS]\n{formula_to_infix(f)}\n").sys_safety[0].formula
    samples = {"a": 0b0101, "b": 0b0011}
    assert evaluate_many(f, samples, samples, 0b1111) == evaluate_many(again, samples, samples, 0b1111)


def test_short_shared_subformulas_are_written_out():
    shared = Or((Var("a"), Var("b")))
    f = And((shared, Not(shared)))
    assert formula_in_words(f) == "(a or b) and not (a or b)"
    assert formula_to_infix(f) == "(a | b) & !(a | b)"

"""Structured English and infix rendering."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from spec_testing import NAMES, SPECS, formulas

from ltl_stack.spec import load_spec, parse_structured
from ltl_stack.spec.english import (
    clause_to_english,
    formula_to_english,
    formula_to_infix,
    formula_to_slugsin,
    spec_to_english,
)
from ltl_stack.spec.formula import FALSE, TRUE, And, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.model import Clause
from ltl_stack.spec.ops import flatten


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
    got = clause_to_english(Clause(f), section)
    assert got == expected, got


def test_names_are_kept_intact():
    f = And((Not(v("not_ready")), v("next_to_door", True), v("and"), Or((v("or_gate"), v("If")))))
    got = formula_to_english(f)
    assert got == "not not_ready and next next_to_door and 'and' and (or_gate or 'If')", got


def test_unknown_section_is_refused():
    with pytest.raises(ValueError, match="unknown section 'sys_goals'"):
        clause_to_english(v("a"), "sys_goals")


def test_thesis_example_reads_as_sentences():
    path = SPECS / "simple" / "simple.slugsin"
    if not path.is_file():
        pytest.skip(f"shared spec {path} is absent")
    spec = load_spec(path)
    got = [clause_to_english(c, "sys_safety") for c in spec.sys_safety]
    assert got == ["always, if next person then next stop_camera",
                   "always, if not next sense_object then next move",
                   "always, if next sense_object then next stop"], got


def test_renderers_handle_very_deep_formulas():
    f = v("a")
    for i in range(5000):
        f = Not(f) if i % 2 else Xor(f, v("b"))
    assert formula_to_english(f).count("exactly one of") == 2500
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
    got = spec_to_english(spec)
    assert got["sys_init"] == ["initially x is 4"], got
    assert got["sys_safety"] == ["always (next x is not 3 or next done)"], got
    assert got["sys_liveness"] == ["infinitely often next x is 0 and done"], got
    assert got["env_init"] == ["initially not (x@2 and x@1)"], got  # the range constraint 0<=x<=5
    # without the integers the bits show
    assert clause_to_english(spec.sys_init[0], "sys_init") == "initially (not x@0.0.5 and not x@1 and x@2)"

"""GR(1) specification model, .slugsin and structured readers/writers, Structured English."""
from ltl_stack.spec.english import clause_to_english, formula_to_english, formula_to_infix, spec_to_english
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import FALSE, TRUE, And, Const, Formula, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.load import load_spec
from ltl_stack.spec.model import SECTIONS, Clause, IntegerVariable, Spec
from ltl_stack.spec.slugsin import formula_to_slugsin, parse_slugsin, write_slugsin
from ltl_stack.spec.structured import parse_structured

__all__ = [
    "FALSE", "TRUE", "And", "Const", "Formula", "Iff", "Implies", "Not", "Or", "Var", "Xor",
    "SECTIONS", "Clause", "IntegerVariable", "Spec",
    "SpecError", "load_spec", "parse_slugsin", "write_slugsin", "formula_to_slugsin", "parse_structured",
    "clause_to_english", "formula_to_english", "formula_to_infix", "spec_to_english",
]

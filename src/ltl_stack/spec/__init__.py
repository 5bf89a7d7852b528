"""GR(1) specification model, .slugsin and structured readers/writers, Structured English."""
from ltl_stack.spec.formula import FALSE, TRUE, And, Const, Formula, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.model import SECTIONS, Clause, IntegerVariable, Spec

__all__ = [
    "FALSE", "TRUE", "And", "Const", "Formula", "Iff", "Implies", "Not", "Or", "Var", "Xor",
    "SECTIONS", "Clause", "IntegerVariable", "Spec",
]

"""GR(1) specification model, .slugsin and structured readers/writers, formulas in words.

The names below are imported on first use (PEP 562 module ``__getattr__``): a tool that reads one
slugsin file does not pay for the English writer and reader (~30 ms of a command's start-up), while
``from ltl_stack.spec import load_spec`` keeps working as before.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from ltl_stack.lazy import lazy_exports

if TYPE_CHECKING:  # pragma: no cover - for type checkers and readers only
    from ltl_stack.spec.errors import SpecError
    from ltl_stack.spec.formula import FALSE, TRUE, And, Const, Formula, Iff, Implies, Not, Or, Var, Xor
    from ltl_stack.spec.formula_text import (
        clause_in_words,
        formula_in_words,
        formula_to_infix,
        spec_in_words,
    )
    from ltl_stack.spec.load import load_spec
    from ltl_stack.spec.model import SECTIONS, Clause, IntegerVariable, Spec
    from ltl_stack.spec.slugsin import formula_to_slugsin, parse_slugsin, write_slugsin
    from ltl_stack.spec.structured import parse_structured

_EXPORTS = {
    "formula_text": ("clause_in_words", "formula_in_words", "formula_to_infix", "spec_in_words"),
    "errors": ("SpecError",),
    "formula": ("FALSE", "TRUE", "And", "Const", "Formula", "Iff", "Implies", "Not", "Or", "Var", "Xor"),
    "load": ("load_spec",),
    "model": ("SECTIONS", "Clause", "IntegerVariable", "Spec"),
    "slugsin": ("formula_to_slugsin", "parse_slugsin", "write_slugsin"),
    "structured": ("parse_structured",),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = [
    "FALSE", "TRUE", "And", "Const", "Formula", "Iff", "Implies", "Not", "Or", "Var", "Xor",
    "SECTIONS", "Clause", "IntegerVariable", "Spec",
    "SpecError", "load_spec", "parse_slugsin", "write_slugsin", "formula_to_slugsin", "parse_structured",
    "clause_in_words", "formula_in_words", "formula_to_infix", "spec_in_words",
]


__getattr__, __dir__ = lazy_exports(__name__, _MODULE_OF, __all__)

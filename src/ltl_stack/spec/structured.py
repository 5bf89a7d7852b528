"""Placeholder until the structured reader lands."""
from __future__ import annotations

from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.model import Spec


def parse_structured(text: str, file: str = "<string>") -> Spec:
    raise SpecError(file, 1, 1, "the structured format is not supported yet")

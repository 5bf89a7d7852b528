"""Spec text assembled by a program: a header, the declarations and each section's clauses with their
comments, in the structured format (infix) or the slugsin format (prefix). One writer for every spec
ltl_stack writes at run time: environment characterization (thesis §4.7, Alg. 2) and integrative
negotiation (§4.8, Alg. 4: phi^nego and the offers)."""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Union

from ltl_stack.spec.formula import Formula
from ltl_stack.spec.formula_text import formula_to_infix
from ltl_stack.spec.model import SECTIONS, SLUGSIN_SECTIONS

#: one line of a section: a text line (a ``str``: a comment, or a clause already written) or a clause
#: (a ``Formula``, rendered)
Entry = Union[str, Formula]  # noqa: UP007 - a runtime alias: Python 3.8 has no str | Formula


def write_spec_text(sections: Mapping[str, Sequence[Entry]], *, header: Sequence[str] = (),
                    inputs: Sequence[str] | None = None, outputs: Sequence[str] | None = None,
                    render: Callable[[Formula], str] = formula_to_infix) -> str:
    """``header`` lines, then ``[INPUT]``/``[OUTPUT]`` (when ``inputs`` is given), then each section of
    ``sections`` in the order of ``SECTIONS`` under its header (``[ENV_TRANS]`` …), each entry a
    text line or a clause rendered with ``render``; a blank line after each block."""
    out = list(header)
    if inputs is not None:
        out += ["[INPUT]", *inputs, "", "[OUTPUT]", *(outputs or ()), ""]
    for section in SECTIONS:
        if section not in sections:
            continue
        out.append(f"[{SLUGSIN_SECTIONS[section]}]")
        out += [entry if isinstance(entry, str) else render(entry) for entry in sections[section]]
        out.append("")
    return "\n".join(out)

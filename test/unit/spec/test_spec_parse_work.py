"""A spec's parse costs work linear in its size: doubling a spec doubles the work.

Work is counted, not timed (the machine is shared): the Python function calls and C calls the
reader makes, seen through ``sys.setprofile``, plus the operands of every ``And``/``Or`` node it
builds (copying a growing operand tuple is one C call but quadratic work). A quadratic step
(re-flattening a chain at every operator, re-scanning a line per word) shows up as a ratio near 4
instead of 2.
"""
from __future__ import annotations

import sys
from collections.abc import Callable

import pytest
from hypothesis import given, settings
from spec_testing import formulas

from ltl_stack.spec import parse_slugsin, write_slugsin
from ltl_stack.spec.formula import And, Or, Var, variables
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.slugsin import valid_name

#: work(2n) / work(n) above this is not linear (constant overheads keep it a little under 2)
LINEAR = 2.25


def calls(fn: Callable[[], object]) -> int:
    """Function calls (Python and C) made while ``fn`` runs, plus the operands of n-ary nodes built."""
    count = 0
    init = And.__init__.__code__

    def profile(frame, event, arg) -> None:
        nonlocal count
        if event == "call":
            count += 1
            if frame.f_code is init or frame.f_code is Or.__init__.__code__:
                count += len(frame.f_locals["args"])
        elif event == "c_call":
            count += 1

    sys.setprofile(profile)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return count


def scaled(n: int, shape: str) -> str:
    """A spec with 2 x n propositions whose clauses each mention all of them once or more."""
    xs, ys = [f"x{i}" for i in range(n)], [f"y{i}" for i in range(n)]

    def left(op: str, parts: list[str]) -> str:
        return " ".join([op] * (len(parts) - 1) + parts)

    def right(op: str, parts: list[str]) -> str:
        return " ".join(w for part in parts[:-1] for w in (op, part)) + " " + parts[-1]

    if shape == "left":
        trans = left("&", [f"| ! {x} {x}'" for x in xs]), left("&", [f"^ {y}' {y}" for y in ys])
    elif shape == "right":
        trans = right("|", [f"& {x} ! {x}'" for x in xs]), right("&", [f"! ^ {y}' {y}" for y in ys])
    elif shape == "buffers":  # $ n entries, each recalling the one before it
        entries = [xs[0]] + [f"^ ? {i} {x}'" for i, x in enumerate(xs[1:])]
        trans = f"$ {n} " + " ".join(entries), left("|", ys)
    elif shape == "and-buffers":  # $ n entries, each the one before it & one more: an entry stays a
        # chain until used, so only the last (used) one becomes a flat And; flattening every entry
        # into the next copied 1 + 2 + ... + n operands
        entries = [f"& {xs[0]} {xs[1]}'"] + [f"& ? {i} {x}'" for i, x in enumerate(xs[2:])]
        trans = f"$ {n - 1} " + " ".join(entries), left("|", ys)
    else:  # many short lines
        trans = "\n".join(f"| ! {x} {x}'" for x in xs), "\n".join(f"^ {y}' {y}" for y in ys)
    return "\n".join(["[INPUT]", *xs, "[OUTPUT]", *ys, "[ENV_TRANS]", trans[0], "[SYS_INIT]",
                      left("&", [f"! {y}" for y in ys]), "[SYS_TRANS]", trans[1], "[SYS_LIVENESS]", "y0", ""])


@pytest.mark.parametrize("shape", ["left", "right", "buffers", "and-buffers", "lines"])
def test_doubling_a_spec_doubles_the_parse_work(shape: str) -> None:
    for n in (200, 800):
        small, large = scaled(n, shape), scaled(2 * n, shape)
        assert 1.9 < len(large) / len(small) < 2.2
        ratio = calls(lambda: parse_slugsin(large)) / calls(lambda: parse_slugsin(small))  # noqa: B023
        assert 1.5 < ratio < LINEAR, (shape, n, ratio)


def _doubled(text: str) -> str:
    """A slugsin text with a renamed copy of every declaration and clause line added (twice the size)."""
    out = []
    for line in text.splitlines():
        out.append(line)
        if line and not line.startswith("["):
            out.append(" ".join(_renamed(w) for w in line.split()))
    return "\n".join(out) + "\n"


def _renamed(word: str) -> str:
    name = word.rstrip("'")
    return f"{name}_copy{word[len(name):]}" if valid_name(name) else word


@settings(max_examples=25, deadline=None)
@given(formulas(max_leaves=40), formulas(max_leaves=40))
def test_doubling_random_specs_doubles_the_parse_work(safety, goal) -> None:
    names = sorted({v.name for v in variables(safety) | variables(goal)}) or ["a"]
    spec = Spec(inputs=names[: len(names) // 2], outputs=names[len(names) // 2:],
                sys_safety=[Clause(safety)] * 20, sys_liveness=[Clause(goal)] * 5)
    small = write_slugsin(spec)
    large = _doubled(small)
    assert parse_slugsin(large).sys_safety[20:] and len(parse_slugsin(large).inputs) == 2 * len(spec.inputs)
    ratio = calls(lambda: parse_slugsin(large)) / calls(lambda: parse_slugsin(small))
    assert ratio < LINEAR, ratio


def test_a_recalled_chain_is_one_shared_flat_formula() -> None:
    """``? i`` of an ``&`` chain entry, used twice, gives one flat ``And`` object, shared as an
    entry settled before it was recalled was."""
    spec = parse_slugsin("[INPUT]\na\nb\nc\n\n[SYS_TRANS]\n$ 2 & a & b c | ? 0 ! ? 0\n")
    entry, negated = spec.sys_safety[0].formula.args
    assert entry == And((Var("a"), Var("b"), Var("c")))
    assert negated.arg is entry

"""Reading a long one-line formula takes memory a small multiple of the line (issue: an 8 MB line
peaked at 64 times its size).

Memory is measured (``tracemalloc``: the Python allocations the reader makes, the text itself not
counted), time is not. Each shape is the densest of its kind, where every few bytes is one node: a
right-nested ``&`` chain (what slugs writes), a left-nested one, a run of ``!``, a ``^`` chain,
infix ``&`` and nested parentheses. The bound (20 times the line, 24 for a run of ``!``) is what the readers promise; before,
these took 45-100 times.
"""
from __future__ import annotations

import tracemalloc

import pytest

from ltl_stack.spec import parse_slugsin, parse_structured

#: the promise: peak allocations while reading, per byte of input; a run of ``!`` is one 40-byte
#: node per 2 bytes, 20 times the line for the formula alone
BOUND = {"not": 24}
SIZE = 300_000  # bytes of the formula line: large enough that fixed costs do not count
NAMES = [f"p{k}" for k in range(10)]
HEADER = "[INPUT]\n" + "\n".join(NAMES) + "\n[SYS_TRANS]\n"


def _line(shape: str) -> str:
    k = SIZE // 5
    if shape == "right":
        return " ".join(f"& {NAMES[i % 10]}" for i in range(k)) + " p0"
    if shape == "left":
        return "& " * k + " ".join(NAMES[i % 10] for i in range(k + 1))
    if shape == "not":
        return "! " * (SIZE // 2) + "p0"
    if shape == "xor":
        return "^ p1 " * k + "p0"
    if shape == "infix":
        return " & ".join(NAMES[i % 10] for i in range(k))
    return "(" * (SIZE // 2) + "p0" + ")" * (SIZE // 2)


@pytest.mark.parametrize("shape", ["right", "left", "not", "xor", "infix", "parentheses"])
def test_a_long_line_is_read_in_memory_a_small_multiple_of_it(shape: str) -> None:
    text = HEADER + _line(shape) + "\n"
    read = parse_structured if shape in ("infix", "parentheses") else parse_slugsin
    tracemalloc.start()
    try:
        spec = read(text, "long.slugsin")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert spec.sys_safety, shape
    assert peak <= BOUND.get(shape, 20) * len(text), (shape, peak / len(text))


def test_formula_nodes_have_slots_and_still_pickle_copy_and_stay_frozen() -> None:
    import copy
    import dataclasses
    import pickle

    from ltl_stack.spec.formula import And, Not, Var, Xor

    f = And((Var("a"), Not(Var("b", True)), Xor(Var("a"), Var("c"))))
    assert not hasattr(Var("a"), "__dict__")  # some 100 bytes a node saved on an 8 MB line
    assert pickle.loads(pickle.dumps(f)) == f
    assert copy.deepcopy(f) == f and hash(copy.deepcopy(f)) == hash(f)
    assert Var("a").primed is False and dataclasses.replace(Var("a"), primed=True) == Var("a", True)
    with pytest.raises(dataclasses.FrozenInstanceError):
        Var("a").name = "b"

"""The .slugsin reader and writer: real specs, buffers, integers, deep chains, errors, round trips."""
from __future__ import annotations

import pytest
from helpers import work
from hypothesis import given, settings
from spec_testing import SPECS, formulas, random_samples, same_content, shared_specs, truth_bits

from ltl_stack.errors import UserError
from ltl_stack.spec import SpecError, load_spec, parse_slugsin, parse_structured, write_slugsin
from ltl_stack.spec.formula import FALSE, TRUE, And, Not, Or, Var, Xor
from ltl_stack.spec.model import Clause, Spec
from ltl_stack.spec.ops import depth, prefix_normal_form
from ltl_stack.spec.slugsin import formula_to_slugsin

ALL_SLUGSIN = shared_specs("**/*.slugsin")


def spec_path(name: str):
    path = SPECS / name / f"{name}.slugsin"
    if not path.is_file():
        pytest.skip(f"shared spec {path} is absent")
    return path


def p(name: str, primed: bool = False) -> Var:
    return Var(name, primed)


def test_simple_spec_reads_exactly():
    spec = load_spec(spec_path("simple"))
    assert spec.inputs == ["person", "sense_object"], spec.inputs
    assert spec.outputs == ["stop_camera", "move", "stop"], spec.outputs
    got = [c.formula for c in spec.sys_safety]
    expected = [
        Or((Not(p("person", True)), p("stop_camera", True))),
        Or((Not(Not(p("sense_object", True))), p("move", True))),
        Or((Not(p("sense_object", True)), p("stop", True))),
    ]
    assert got == expected, got
    assert spec.sys_init == [], spec.sys_init
    assert [c.formula for c in spec.env_init] == [TRUE]
    first = spec.sys_safety[0]
    assert (first.text, first.line, first.file) == ("| ! person' stop_camera'", 20, str(spec_path("simple"))), first
    assert spec.source == str(spec_path("simple"))


def test_thesis_examples_load():
    clean = load_spec(spec_path("move_group_and_move_base"))
    assert "holdingObject" in clean.outputs and "object" in clean.inputs
    assert len(clean.env_safety) > 30, len(clean.env_safety)
    spheros = load_spec(spec_path("spheros"))
    assert spheros.inputs == ["left_arrow", "right_arrow", "up_arrow", "down_arrow", "stop_sign"], spheros.inputs
    assert len(spheros.sys_safety) == 6, spheros.sys_safety
    # | ! ! | | | | left' right' up' down' stop' turn_white'  ->  Or(Not(Not(Or(5 args))), turn_white')
    last = spheros.sys_safety[-1].formula
    assert isinstance(last, Or) and isinstance(last.args[0].arg.arg, Or), last
    assert len(last.args[0].arg.arg.args) == 5, last


@pytest.mark.skipif(not ALL_SLUGSIN, reason="../shared/specs is absent")
@pytest.mark.parametrize("path", ALL_SLUGSIN, ids=lambda q: q.name)
def test_every_shared_slugsin_loads_and_round_trips(path):
    spec = load_spec(path)
    assert spec.propositions, path
    again = parse_slugsin(write_slugsin(spec), "again.slugsin")
    same_content(spec, again)


def test_compiled_integers_are_recognised():
    path = SPECS / "benchmarks" / "slugsin" / "water_reservoir.slugsin"
    if not path.is_file():
        pytest.skip(f"shared spec {path} is absent")
    spec = load_spec(path)
    assert [(v.name, v.low, v.high, len(v.bits)) for v in spec.integers] == [("level", 3, 107, 7)], spec.integers
    assert spec.integers[0].bits[:2] == ("level@0.3.107", "level@1"), spec.integers


def test_buffers_refer_to_earlier_entries_of_the_innermost_buffer():
    text = "[INPUT]\na\nb\n[OUTPUT]\nc\n[SYS_TRANS]\n$ 3 | a b & ? 0 c ^ ? 1 $ 2 ! a & ? 0 b\n"
    spec = parse_slugsin(text)
    entry0 = Or((p("a"), p("b")))
    entry1 = And((entry0, p("c")))
    inner = And((Not(p("a")), p("b")))  # ? 0 inside the nested buffer is its own entry 0
    assert spec.sys_safety[0].formula == Xor(entry1, inner), spec.sys_safety[0].formula


def test_buffer_entries_are_shared_objects_and_the_writer_keeps_them_shared():
    text = "[INPUT]\na\nb\n[OUTPUT]\nc\n[SYS_TRANS]\n$ 2 ^ a b & ? 0 | c ? 0\n"
    formula = parse_slugsin(text).sys_safety[0].formula
    assert formula.args[0] is formula.args[1].args[1], formula
    assert formula_to_slugsin(formula) == "$ 2 ^ a b & ? 0 | c ? 0", formula_to_slugsin(formula)


def test_glued_buffer_syntax_and_comments():
    text = "# a comment\n[INPUT]\na # trailing\n[OUTPUT]\nc\n[SYS_INIT]\n$2 ! a & ?0 c   # why\n"
    spec = parse_slugsin(text)
    assert spec.sys_init[0].formula == And((Not(p("a")), p("c"))), spec.sys_init
    assert spec.sys_init[0].text == "$2 ! a & ?0 c", spec.sys_init[0].text


def test_chains_are_flattened_both_ways():
    text = "[INPUT]\na\nb\nc\nd\n[OUTPUT]\n[ENV_INIT]\n& & & a b c d\n& a & b & c d\n| a | | b c d\n"
    spec = parse_slugsin(text)
    four = (p("a"), p("b"), p("c"), p("d"))
    assert [c.formula for c in spec.env_init] == [And(four), And(four), Or(four)], spec.env_init


def test_deep_prefix_chains_parse_without_recursion():
    n = 20000
    names = [f"v{i}" for i in range(n + 1)]
    chains = " ".join(["&"] * n + names)
    nots = "! " * 5000 + "v0"
    text = "[INPUT]\n" + "\n".join(names) + "\n[OUTPUT]\n[ENV_INIT]\n" + chains + "\n" + nots + "\n"
    spec = parse_slugsin(text)  # the time it takes is a benchmark's business (test_long_chains_... below)
    conj = spec.env_init[0].formula
    assert isinstance(conj, And) and len(conj.args) == n + 1, type(conj)
    assert depth(spec.env_init[1].formula) == 5001
    assert formula_to_slugsin(spec.env_init[1].formula) == nots


def test_integer_declarations_in_slugsin_are_bit_blasted_with_range_constraints():
    text = "[INPUT]\nx:0...5\n[OUTPUT]\ny: 2...5\n[SYS_TRANS]\n| x@2' y@1\n"
    spec = parse_slugsin(text, "ints.slugsin")
    assert spec.inputs == ["x@0.0.5", "x@1", "x@2"], spec.inputs
    assert spec.outputs == ["y@0.2.5", "y@1"], spec.outputs  # four values: no constraint
    assert [(v.name, v.low, v.high) for v in spec.integers] == [("x", 0, 5), ("y", 2, 5)]
    assert [(c.text, c.line) for c in spec.env_init] == [("0<=x<=5", 2)], spec.env_init
    assert [c.text for c in spec.env_safety] == ["0<=x'<=5"], spec.env_safety
    assert spec.sys_init == [] and len(spec.sys_safety) == 1
    # The constraint holds exactly for the bit patterns 0..5.
    for value in range(8):
        current = {b: int(value >> i & 1) for i, b in enumerate(spec.integers[0].bits)}
        got = truth_bits(spec.env_init[0].formula, (current, {}, 1))
        assert got == (1 if value <= 5 else 0), (value, got)


def error_of(text: str, file: str = "bad.slugsin") -> str:
    with pytest.raises(SpecError) as info:
        parse_slugsin(text, file)
    return str(info.value)


@pytest.mark.parametrize("text, expected", [
    ("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\n| a foo\n",
     "bad.slugsin:6:5: undeclared proposition 'foo' (declare it in [INPUT] or [OUTPUT])"),
    ("[INPUT]\na\n[OUTPUT]\nb\n[SYS_INIT]\n& a b'\n",
     "bad.slugsin:6:5: next-state variable b' in an init clause ([SYS_INIT] describes only the first state)"),
    ("[INPUT]\na\n[OUTPUT]\nb\n[ENV_INIT]\n| ! a'\n",
     "bad.slugsin:6:5: next-state variable a' in an init clause ([ENV_INIT] describes only the first state)"),
    ("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\n| a &\n",
     "bad.slugsin:6:6: expected an operand after '&' at column 5"),
    ("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\n| a\n",
     "bad.slugsin:6:4: expected a second operand for '|' at column 1"),
    ("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\n| a b a\n",
     "bad.slugsin:6:7: unexpected 'a' after a complete formula (a slugsin clause is one prefix formula per line)"),
    ("[INPUT]\na\n[OUTPUT]\nb\n[FOO]\n",
     "bad.slugsin:5:1: unknown section [FOO]; expected one of [INPUT], [OUTPUT], [ENV_INIT], [SYS_INIT], "
     "[ENV_TRANS], [SYS_TRANS], [ENV_LIVENESS], [SYS_LIVENESS]"),
    ("a\n[INPUT]\n", "bad.slugsin:1:1: expected a section header such as [INPUT] before the first clause"),
    ("[INPUT] a\n", "bad.slugsin:1:1: a section header stands alone on its line, like [SYS_TRANS]"),
    ("[INPUT]\na\n[OUTPUT]\na\n", "bad.slugsin:4:1: 'a' is declared twice (first as proposition at line 2)"),
    ("[INPUT]\nx:0...3\n[OUTPUT]\nx\n", "bad.slugsin:4:1: 'x' is declared twice (first as integer at line 2)"),
    ("[INPUT]\nx\n[OUTPUT]\nx: 0...3\n", "bad.slugsin:4:1: 'x' is declared twice (first as proposition at line 2)"),
    ("[INPUT]\nx:0...3\nx:0...1\n", "bad.slugsin:3:1: 'x' is declared twice (first as integer at line 2)"),
    ("[INPUT]\nx:0...3\n[OUTPUT]\nx@1\n",
     "bad.slugsin:4:1: 'x@1' is declared twice (first as a bit of integer x at line 2)"),
    ("[INPUT]\nx:4...3\n", "bad.slugsin:2:1: integer 'x' has an empty range 4...3 (lower bound above upper)"),
    ("[INPUT]\na b\n", "bad.slugsin:2:3: one proposition per line in [INPUT]; unexpected 'b'"),
    ("[INPUT]\n&\n", "bad.slugsin:2:1: invalid proposition name '&': a slugsin name is one word without a "
                     "prime that is not an operator or a number"),
    ("[INPUT]\na'\n", "bad.slugsin:2:1: a declared name cannot contain a prime: 'a'' (write x' only in clauses)"),
    ("[INPUT]\na\n[OUTPUT]\n[ENV_TRANS]\n& ? 0 a\n",
     "bad.slugsin:5:3: '?' outside a '$' buffer (? i refers to entry i of the enclosing $ n)"),
    ("[INPUT]\na\n[OUTPUT]\n[ENV_TRANS]\n$ 2 a ? 1\n",
     "bad.slugsin:5:9: '? 1' refers to an entry that is not complete yet: the buffer at column 1 has 1 "
     "complete entry (0...0)"),
    ("[INPUT]\na\n[OUTPUT]\n[ENV_TRANS]\n$ 3 a ! a\n",
     "bad.slugsin:5:10: expected 1 more entry of the '$ 3' buffer at column 1"),
    ("[INPUT]\na\n[OUTPUT]\n[ENV_TRANS]\n$ 0 a\n",
     "bad.slugsin:5:3: expected a positive number of entries after '$', got '0'"),
    ("[INPUT]\na\n[OUTPUT]\n[ENV_TRANS]\n! a''\n",
     "bad.slugsin:5:3: 'a''' has more than one prime; x' is the next state of x"),
])
def test_malformed_input_gives_one_located_error(text, expected):
    assert error_of(text) == expected


def test_error_fields_and_missing_file(tmp_path):
    with pytest.raises(SpecError) as info:
        parse_slugsin("[INPUT]\na\n[OUTPUT]\n[ENV_TRANS]\n& a zz\n", "f.slugsin")
    e = info.value
    assert (e.file, e.line, e.column, e.message) == ("f.slugsin", 5, 5, e.message), e
    assert "zz" in e.message
    missing = tmp_path / "nope.slugsin"
    with pytest.raises(SpecError) as info:
        load_spec(missing)
    assert str(info.value) == f"{missing}: no such file", str(info.value)
    with pytest.raises(SpecError) as info:
        load_spec(tmp_path)
    assert str(info.value) == f"{tmp_path}: is a directory, not a spec file", str(info.value)


@settings(max_examples=300, deadline=None)
@given(formulas())
def test_writer_round_trips_any_formula_to_its_prefix_normal_form(f):
    spec = Spec(inputs=["a", "b", "c", "not_ready"], outputs=["x@0.0.5", "x@1"],
                sys_safety=[Clause(f)], env_liveness=[Clause(f), Clause(TRUE)])
    again = parse_slugsin(write_slugsin(spec))
    expected = prefix_normal_form(f)
    assert again.sys_safety[0].formula == expected, (f, expected)
    assert again.env_liveness[0].formula == expected
    # and a formula already in normal form comes back unchanged
    assert parse_slugsin(write_slugsin(again)).sys_safety[0].formula == expected


@settings(max_examples=200, deadline=None)
@given(formulas())
def test_prefix_normal_form_is_equivalent(f):
    samples = random_samples(["a", "b", "c", "not_ready", "x@0.0.5", "x@1"], 64, seed=7)
    assert truth_bits(prefix_normal_form(f), samples) == truth_bits(f, samples)


def test_writer_comments_name_the_source_and_empty_sections_mean_true():
    spec = Spec(inputs=["a"], outputs=["b"], sys_safety=[Clause(Or((Not(p("a")), FALSE)), "a -> false", "s.ltl", 3)])
    text = write_slugsin(spec, comments=True)
    assert "# s.ltl:3: a -> false\n| ! a 0\n" in text, text
    again = parse_slugsin(text)
    assert again.env_init == [] and again.sys_liveness == [], again


def test_byte_order_mark_and_windows_line_ends(tmp_path):
    path = tmp_path / "w.slugsin"
    path.write_bytes("\ufeff[INPUT]\r\na\r\n[OUTPUT]\r\nb\r\n[SYS_TRANS]\r\n| ! a b'\r\n".encode())
    spec = load_spec(path)
    assert spec.inputs == ["a"] and spec.sys_safety[0].formula == Or((Not(p("a")), p("b", True))), spec
    binary = tmp_path / "b.slugsin"
    binary.write_bytes(b"[INPUT]\n\xff\xfe\n")
    with pytest.raises(SpecError) as info:
        load_spec(binary)
    assert str(info.value) == f"{binary}:2: not a text spec file: not UTF-8 at byte 8", str(info.value)
    assert info.value.code == 2 and isinstance(info.value, UserError)


def _read_chain(n: int, nesting: str) -> None:
    names = [f"v{i}" for i in range(n + 1)]
    header = "[INPUT]\n" + "\n".join(names) + "\n[OUTPUT]\n[ENV_INIT]\n"
    if nesting == "left":
        spec = parse_slugsin(header + " ".join(["&"] * n + names) + "\n")
    elif nesting == "right":
        spec = parse_slugsin(header + " ".join(w for name in names[:-1] for w in ("|", name)) + f" {names[-1]}\n")
    else:
        spec = parse_structured(header + " & ".join(names) + "\n")
    assert len(spec.env_init[0].formula.args) == n + 1


def _operands(frame) -> int:
    """Copying a growing operand tuple is one C call but work linear in its length: count it."""
    if frame.f_code in (And.__init__.__code__, Or.__init__.__code__):
        return len(frame.f_locals["args"])
    return 0


@pytest.mark.parametrize("nesting", ["left", "right", "infix"])
def test_long_chains_read_in_linear_work(nesting):
    # work (calls and operands copied) is counted, never timed: 8x the input is about 8x the work when
    # linear, about 64x when quadratic
    small = work(lambda: _read_chain(1000, nesting), _operands)
    large = work(lambda: _read_chain(8000, nesting), _operands)
    assert 7 < large / small < 9, (small, large)


def test_writer_refuses_names_slugsin_cannot_hold():
    with pytest.raises(ValueError, match="proposition 'two words' cannot be written in slugsin"):
        write_slugsin(Spec(inputs=["two words"]))

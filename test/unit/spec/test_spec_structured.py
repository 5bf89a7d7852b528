"""The structured (infix) reader: shared specs, equivalence with slugs' compiled output, integers, errors."""
from __future__ import annotations

import itertools
from dataclasses import replace

import pytest
from spec_testing import random_samples, same_content, shared_specs, truth_bits

from ltl_stack.spec import SpecError, load_spec, parse_slugsin, parse_structured, write_slugsin
from ltl_stack.spec.formula import FALSE, TRUE, And, Iff, Implies, Not, Or, Var, Xor
from ltl_stack.spec.model import SECTIONS
from ltl_stack.spec.ops import prefix_normal_form

ALL_STRUCTURED = shared_specs("**/*.structuredslugs")
COMPILED = {p.stem: p for p in shared_specs("**/*.slugsin")}
PAIRS = [(p, COMPILED[p.stem]) for p in ALL_STRUCTURED if p.stem in COMPILED]

HEADER = "[INPUT]\na\nb\nc\nx:0...5\n[OUTPUT]\nd\ny:2...5\n"


def formula(clause: str, section: str = "SYS_TRANS"):
    spec = parse_structured(f"{HEADER}[{section}]\n{clause}\n", "t.structuredslugs")
    return spec.section({"SYS_TRANS": "sys_safety", "SYS_INIT": "sys_init", "ENV_LIVENESS": "env_liveness"}[section])[0].formula


def v(name: str, primed: bool = False) -> Var:
    return Var(name, primed)


@pytest.mark.skipif(not ALL_STRUCTURED, reason="../shared/specs is absent")
@pytest.mark.parametrize("path", ALL_STRUCTURED, ids=lambda q: q.name)
def test_every_shared_structured_spec_loads_and_writes_as_slugsin(path):
    spec = load_spec(path)
    assert spec.propositions, path
    assert all(c.file == str(path) and c.line > 0 for name in SECTIONS for c in spec.section(name))
    again = parse_slugsin(write_slugsin(spec), "again.slugsin")
    # slugsin has no -> and <->, and 1-value integers have no bits to write
    expected = replace(spec, integers=[v for v in spec.integers if v.bits], **{
        name: [replace(c, formula=prefix_normal_form(c.formula)) for c in spec.section(name)] for name in SECTIONS})
    same_content(expected, again)


@pytest.mark.skipif(not PAIRS, reason="../shared/specs is absent")
@pytest.mark.parametrize("structured, compiled", PAIRS, ids=lambda q: q.stem)
def test_structured_specs_mean_what_slugs_compiled_them_to(structured, compiled):
    ours = load_spec(structured)
    theirs = load_spec(compiled)
    assert ours.inputs == theirs.inputs, (ours.inputs, theirs.inputs)
    assert ours.outputs == theirs.outputs, (ours.outputs, theirs.outputs)
    assert [v for v in ours.integers if v.bits] == theirs.integers, (ours.integers, theirs.integers)
    samples = random_samples(ours.propositions, 512, seed=len(structured.stem))
    for name in SECTIONS:
        mine, slugs = ours.section(name), theirs.section(name)
        assert len(mine) == len(slugs), (name, len(mine), len(slugs))
        for a, b in zip(mine, slugs):
            assert truth_bits(a.formula, samples) == truth_bits(b.formula, samples), (name, a.text, b.line)


@pytest.mark.parametrize("text, expected", [
    ("a | b & c", Or((v("a"), And((v("b"), v("c")))))),
    ("a & b | c", Or((And((v("a"), v("b"))), v("c")))),
    ("a -> b -> c", Implies(v("a"), Implies(v("b"), v("c")))),
    ("a <-> b -> c", Iff(v("a"), Implies(v("b"), v("c")))),
    ("a ^ b | c", Xor(v("a"), Or((v("b"), v("c"))))),
    ("!a & b", And((Not(v("a")), v("b")))),
    ("!(a & b')", Not(And((v("a"), v("b", True))))),
    ("~a && b /\\ c", And((Not(v("a")), v("b"), v("c")))),
    ("a || b \\/ c --> d'", Implies(Or((v("a"), v("b"), v("c"))), v("d", True))),
    ("(a <--> b)", Iff(v("a"), v("b"))),
    ("TRUE & FALSE | 1 & 0", Or((And((TRUE, FALSE)), And((TRUE, FALSE))))),
    ("(a & (b & c)) & d", And((v("a"), v("b"), v("c"), v("d")))),
    ("! ! a", Not(Not(v("a")))),
    ("| ! a b'", Or((Not(v("a")), v("b", True)))),  # a slugsin line passed through
    ("$ 2 a & ? 0 b", And((v("a"), v("b")))),
])
def test_infix_precedence_and_spellings(text, expected):
    got = formula(text)
    assert got == expected, got


@pytest.mark.parametrize("text, meaning", [
    ("x = 3", lambda x, y, x2, y2: x == 3),
    ("x' != y", lambda x, y, x2, y2: x2 != y),
    ("x < 4", lambda x, y, x2, y2: x < 4),
    ("x+1 = y'", lambda x, y, x2, y2: x + 1 == y2),
    ("x + y >= 7", lambda x, y, x2, y2: x + y >= 7),
    ("y > x' + 2", lambda x, y, x2, y2: y > x2 + 2),
    ("y <= 3 & x' >= 6", lambda x, y, x2, y2: y <= 3 and x2 >= 6),
    ("x + 1 + y' = 9 | !(y = 2)", lambda x, y, x2, y2: x + 1 + y2 == 9 or y != 2),
])
def test_integer_comparisons_are_exact_on_every_bit_pattern(text, meaning):
    f = formula(text)
    x_bits = ("x@0.0.5", "x@1", "x@2")
    y_bits = ("y@0.2.5", "y@1")
    for x, y, x2, y2 in itertools.product(range(8), range(4), range(8), range(4)):
        current = {**{b: x >> i & 1 for i, b in enumerate(x_bits)}, **{b: y >> i & 1 for i, b in enumerate(y_bits)}}
        nxt = {**{b: x2 >> i & 1 for i, b in enumerate(x_bits)}, **{b: y2 >> i & 1 for i, b in enumerate(y_bits)}}
        for name in ("a", "b", "c", "d"):
            current[name] = nxt[name] = 0
        got = truth_bits(f, (current, nxt, 1))
        expected = int(meaning(x, 2 + y, x2, 2 + y2))  # value = low + unsigned bits, even out of range
        assert got == expected, (text, x, y, x2, y2, got)


def test_integers_declare_bits_and_range_constraints():
    spec = parse_structured(HEADER + "[SYS_INIT]\ny = 4\n", "t.ltl")
    assert spec.inputs == ["a", "b", "c", "x@0.0.5", "x@1", "x@2"], spec.inputs
    assert spec.outputs == ["d", "y@0.2.5", "y@1"], spec.outputs
    assert [(c.text, c.line) for c in spec.env_init] == [("0<=x<=5", 5)], spec.env_init
    assert [c.text for c in spec.env_safety] == ["0<=x'<=5"], spec.env_safety
    assert [c.text for c in spec.sys_init] == ["y = 4"], spec.sys_init  # y:2...5 has exactly 4 values


def test_one_value_integers_have_no_bits_and_compare_as_constants():
    spec = parse_structured("[INPUT]\ng: 0...0\n[OUTPUT]\n[ENV_TRANS]\ng' >= g + 1\ng = 0\n")
    assert spec.inputs == [] and [(i.name, i.bits) for i in spec.integers] == [("g", ())], spec.integers
    assert [c.formula for c in spec.env_safety] == [FALSE, TRUE], spec.env_safety


def error_of(text: str) -> str:
    with pytest.raises(SpecError) as info:
        parse_structured(text, "bad.structuredslugs")
    return str(info.value)


@pytest.mark.parametrize("clause, expected", [
    ("a & foo", "10:5: undeclared proposition 'foo' (declare it in [INPUT] or [OUTPUT])"),
    ("a &", "10:4: expected an operand after '&' at column 3"),
    ("a & | b", "10:5: expected an operand after '&', got '|'"),
    ("(a | b", "10:7: expected ')' to close the '(' at column 1"),
    ("a | b)", "10:6: unexpected ')' without a matching '('"),
    ("a b", "10:3: expected an operator such as '&', '|' or '->' before 'b'"),
    ("a = 3", "10:1: 'a' is a Boolean proposition; only integer variables (name:lo...hi) can be compared or added"),
    ("x", "10:1: integer variable 'x' needs a comparison, such as x = 0"),
    ("x' & a", "10:1: integer variable 'x' needs a comparison, such as x' = 0"),
    ("x - 1 = y", "10:3: operator '-' is not supported in integer expressions; only '+' is"),
    ("x + a = 1", "10:5: 'a' is a Boolean proposition, not an integer"),
    ("x + = 1", "10:5: expected a number or an integer variable, got '='"),
    ("x = z", "10:5: undeclared integer variable 'z' (declare it as name:lo...hi in [INPUT] or [OUTPUT])"),
    ("x +", "10:4: expected a number or an integer variable after '+'"),
    ("x + 1", "10:6: expected a comparison (= != < <= > >=) after the integer expression"),
    ("3", "10:1: the number 3 is not a formula; compare it with an integer variable, as in x = 3"),
    ("a % b", "10:3: unexpected character '%'"),
    ("a'' | b", "10:1: 'a''' has more than one prime; x' is the next state of x"),
])
def test_malformed_clauses_give_one_located_error(clause, expected):
    assert error_of(f"{HEADER}[SYS_TRANS]\n{clause}\n") == f"bad.structuredslugs:{expected}"


def test_next_state_variables_are_refused_in_init_clauses():
    message = "next-state variable {}' in an init clause ([SYS_INIT] describes only the first state)"
    assert error_of(f"{HEADER}[SYS_INIT]\nd & a'\n") == "bad.structuredslugs:10:5: " + message.format("a")
    assert error_of(f"{HEADER}[SYS_INIT]\ny' = 3\n") == "bad.structuredslugs:10:1: " + message.format("y")
    assert formula("a' | x' = 1", "ENV_LIVENESS") is not None  # primes are fine in liveness


def test_load_spec_picks_the_reader(tmp_path):
    infix = tmp_path / "task.ltl"
    infix.write_text("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\na -> b'\n")
    assert load_spec(infix).sys_safety[0].formula == Implies(v("a"), v("b", True))
    unknown = tmp_path / "task.spec"
    unknown.write_text("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\na -> b'\n")
    assert load_spec(unknown).sys_safety[0].formula == Implies(v("a"), v("b", True))
    prefix = tmp_path / "other.txt"
    prefix.write_text("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\n| ! a b'\n")
    assert load_spec(prefix).sys_safety[0].formula == Or((Not(v("a")), v("b", True)))
    broken = tmp_path / "broken.txt"
    broken.write_text("[INPUT]\na\n[OUTPUT]\nb\n[SYS_TRANS]\na -> c'\n")
    with pytest.raises(SpecError) as info:
        load_spec(broken)
    assert str(info.value) == f"{broken}:6:6: undeclared proposition 'c' (declare it in [INPUT] or [OUTPUT])"


@pytest.mark.parametrize("text, meaning", [
    ("z < 0", lambda z: z < 0),
    ("z + 3 = 4", lambda z: z + 3 == 4),
    ("z >= -0 + 1", None),
    ("1 + z != z + 1", lambda z: False),
])
def test_negative_lower_bounds(text, meaning):
    header = "[INPUT]\nz: -3...2\n[OUTPUT]\n[ENV_TRANS]\n"
    if meaning is None:  # there are no negative constants, as in slugs
        with pytest.raises(SpecError, match="expected a number or an integer variable, got '-'"):
            parse_structured(header + text + "\n")
        return
    spec = parse_structured(header + text + "\n")
    assert spec.inputs == ["z@0.-3.2", "z@1", "z@2"], spec.inputs
    f = spec.env_safety[0].formula
    for bits in range(8):
        current = {b: bits >> i & 1 for i, b in enumerate(spec.inputs)}
        got = truth_bits(f, (current, {}, 1))
        assert got == int(meaning(-3 + bits)), (text, bits, got)

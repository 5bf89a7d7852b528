"""LTLMoP's region bits and follow macros in raw LTL (``parser: ltl``, ``use_region_bit_encoding``).

``guide.spec`` (our own project in LTLMoP's format) follows a visitor whose room arrives as the
sensor bits ``sbit0``, ``sbit1``; its map ``corridor.regions`` has three rooms in a row, numbered
entrance 0 (00), gallery 1 (01), shop 2 (10); pattern 11 names no region. The expected formulas are
LTLMoP's expansion (``specCompiler.substituteMacros``, ``createTopologyFragment``, ``bitEncoding``,
read for the facts) written by hand in the structured format's infix. LTLMoP's own verdicts on these
files (its compiler with JTLV, run by hand): guide.spec realizable, with ``[](!s.shop)`` unrealizable,
with ``[](next(s.wave) = next(s.visitor_waits) & FALSE)`` unrealizable."""
from __future__ import annotations

from pathlib import Path

import pytest
from english_testing import Bdds
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.spec import load_spec
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.structured import parse_structured
from ltl_stack.synthesis import is_realizable

DATA = Path(__file__).resolve().parents[2] / "data" / "ltlmop"
GUIDE = DATA / "guide.spec"
NAMES = ["sbit0", "sbit1", "wave", "visitor_waits", "entrance", "gallery", "shop"]
SIGNATURE = "[INPUT]\nsbit0\nsbit1\n[OUTPUT]\nwave\nvisitor_waits\nentrance\ngallery\nshop\n"
# region number i as bits, most significant first; the robot's bits are disjunctions of its regions
ENTRANCE, GALLERY, SHOP = "(!sbit0 & !sbit1)", "(!sbit0 & sbit1)", "(sbit0 & !sbit1)"
BIT0, BIT1 = "shop", "gallery"


def _next(pattern: str) -> str:
    return pattern.replace("sbit0", "sbit0'").replace("sbit1", "sbit1'")


def _section(spec, section: str, lines: set[int] | None = None):
    bdds = Bdds(NAMES)
    out = bdds.bdd.true
    for clause in spec.section(section):
        if lines is None or clause.line in lines:
            out &= bdds.of(clause.formula)
    return out, bdds


def _expected(header: str, infix: list[str], bdds: Bdds):
    spec = parse_structured(SIGNATURE + f"[{header}]\n" + "\n".join(infix) + "\n", "e.ltl")
    out = bdds.bdd.true
    for clause in spec.env_init + spec.env_safety + spec.sys_init + spec.sys_safety + spec.sys_liveness:
        out &= bdds.of(clause.formula)
    return out


def _variant(tmp_path: Path, old: str, new: str) -> Path:
    text = GUIDE.read_text()
    assert old in text
    (tmp_path / "corridor.regions").write_text((DATA / "corridor.regions").read_text())
    path = tmp_path / "guide.spec"
    path.write_text(text.replace(old, new))
    return path


def test_follow_macro_is_the_topology_mirrored_onto_the_target_bits():
    spec = load_spec(GUIDE)
    assert spec.inputs == ["sbit0", "sbit1"]
    got, bdds = _section(spec, "env_safety")
    valid = f"{ENTRANCE} | {GALLERY} | {SHOP}"
    expected = _expected("ENV_TRANS", [
        f"{ENTRANCE} -> ({_next(ENTRANCE)} | {_next(GALLERY)})",
        f"{GALLERY} -> ({_next(GALLERY)} | {_next(ENTRANCE)} | {_next(SHOP)})",
        f"{SHOP} -> ({_next(SHOP)} | {_next(GALLERY)})",
        valid,
    ], bdds)
    assert got == expected
    got_init, bdds = _section(spec, "env_init")
    assert got_init == _expected("ENV_INIT", [valid], bdds)
    assert got_init != bdds.bdd.true  # pattern 11 is excluded


def test_region_bits_and_target_is_stationary_read_as_ltlmop_means_them():
    spec = load_spec(GUIDE)
    got, bdds = _section(spec, "sys_safety", {42, 44})
    expected = _expected("SYS_TRANS", [
        "visitor_waits' <-> ((sbit0' <-> sbit0) & (sbit1' <-> sbit1))",
        f"wave' -> (visitor_waits' & ({BIT0}' <-> sbit0') & ({BIT1}' <-> sbit1'))",
    ], bdds)
    assert got == expected
    goals = [c for c in spec.sys_liveness if c.line == 46]
    bdds = Bdds(NAMES)
    assert len(goals) == 1
    assert bdds.of(goals[0].formula) == _expected(
        "SYS_LIVENESS", [f"visitor_waits -> (({BIT0} <-> sbit0) & ({BIT1} <-> sbit1))"], bdds)


def test_verdicts_are_ltlmops(tmp_path):
    assert is_realizable(load_spec(GUIDE))
    # the visitor may wait in the shop, where the robot must not go
    assert not is_realizable(load_spec(_variant(tmp_path, "s.entrance & !s.wave\n",
                                                "s.entrance & !s.wave\n[](!s.shop)\n")))


def test_equals_binds_tighter_than_and(tmp_path):
    path = _variant(tmp_path, "[](next(s.wave) -> next(s.visitor_waits) & next(s.bit0) = next(e.sbit0) & "
                              "next(s.bit1) = next(e.sbit1))",
                    "[](next(s.wave) = next(s.visitor_waits) & FALSE)")
    assert not is_realizable(load_spec(path))  # (wave' <-> visitor_waits') & FALSE, as in LTLMoP


def test_the_numbering_of_the_regions_is_said(tmp_path):
    spec = load_spec(GUIDE)
    assert len(spec.warnings) == 1
    assert "number the regions 0 entrance, 1 gallery, 2 shop" in spec.warnings[0]


def test_follow_without_bit_encoding_is_refused_naming_the_option(tmp_path):
    path = _variant(tmp_path, "use_region_bit_encoding: True", "use_region_bit_encoding: False")
    with pytest.raises(SpecError) as caught:
        load_spec(path)
    message = str(caught.value)
    assert message.startswith(f"{path}:36:") and "use_region_bit_encoding: True (line 16)" in message
    assert "\n" not in message


def test_follow_sensors_are_added_when_the_project_omits_them(tmp_path):
    path = _variant(tmp_path, "sbit0, 1\nsbit1, 1\n", "sbit1, 0\n")
    spec = load_spec(path)
    assert sorted(spec.inputs) == ["sbit0", "sbit1"]  # LTLMoP adds the target's bits to the sensors
    assert is_realizable(spec)


def test_follow_inside_a_formula_is_refused(tmp_path):
    path = _variant(tmp_path, "\nFOLLOW_SENSOR_CONSTRAINTS\n", "\nTRUE & FOLLOW_SENSOR_CONSTRAINTS\n")
    with pytest.raises(SpecError, match="on a line of its own"):
        load_spec(path)


@settings(max_examples=60, deadline=None)
@given(n=st.integers(min_value=2, max_value=20), data=st.data())
def test_a_bit_pattern_is_the_region_with_that_number(n, data):
    """Where the robot is in exactly one of n regions, LTLMoP's pattern of number i (``s.bitJ``
    literals, most significant first) holds exactly in region i, and a number >= n in none."""
    from ltl_stack.spec.activation_completion import exactly_one
    from ltl_stack.spec.ltlmop_project import _RawLtl
    from ltl_stack.spec.structured_english import Declarations

    regions = [f"r{k}" for k in range(n)]
    width = (n - 1).bit_length()
    i = data.draw(st.integers(min_value=0, max_value=2 ** width - 1))
    raw = _RawLtl(Declarations(regions=regions, regions_are_places=True), "t.spec", True, {})
    pattern = " & ".join(f"{'' if (i >> (width - 1 - j)) & 1 else '!'}s.bit{j}" for j in range(width))
    _, infix = raw._to_infix(pattern, 1)
    signature = "[OUTPUT]\n" + "".join(r + "\n" for r in regions)
    formula = parse_structured(signature + f"[SYS_INIT]\n{infix}\n", "e.ltl").sys_init[0].formula
    bdds = Bdds(regions)
    one = bdds.of(exactly_one(regions, False))
    assert one & bdds.of(formula) == (one & bdds.bdd.var(f"r{i}") if i < n else bdds.bdd.false)


def test_a_declared_proposition_named_like_a_region_bit_is_refused(tmp_path):
    path = _variant(tmp_path, "Customs: # robot propositions of the task\nvisitor_waits\n",
                    "Customs: # robot propositions of the task\nvisitor_waits\nbit1\n")
    with pytest.raises(SpecError, match=r"guide.spec:45:\d+: 'bit1' is declared and is also LTLMoP's region bit 1"):
        load_spec(path)


def test_region_bits_with_fastslow_are_refused(tmp_path):
    path = _variant(tmp_path, "fastslow: False", "fastslow: True")
    with pytest.raises(SpecError, match=r"guide.spec:44:\d+: the region bit 'bit0' .*\(fastslow: False\)"):
        load_spec(path)

"""Parsing and printing of valuations typed by users (``a=1,b=0``, ``a !b``)."""
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.spec.valuation import format_valuation, parse_valuation


def test_parse_mixed_forms():
    got = parse_valuation("a=1, b=false, !c, d")
    assert got == {"a": True, "b": False, "c": False, "d": True}, got


@pytest.mark.parametrize("text,message", [
    ("a=maybe", "a=true or a=false"),
    ("a=1,a=0", "both true and false"),
    ("a b", "not a proposition name"),
    ("zz=1", "unknown proposition 'zz'"),
])
def test_parse_errors_name_the_item(text, message):
    with pytest.raises(ValueError, match=message):
        parse_valuation(text, known=["a", "b"] if text.startswith("zz") else None)


names = st.from_regex(r"[a-z][a-z0-9_]{0,8}", fullmatch=True)


@given(st.dictionaries(names, st.booleans(), max_size=6))
def test_format_then_parse_round_trips(valuation):
    text = format_valuation(valuation).replace(" ", ",")
    assert parse_valuation(text) == valuation

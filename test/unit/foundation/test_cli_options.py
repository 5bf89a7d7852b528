"""The toolkit's number option types and the all-or-none writing of several outputs."""
from __future__ import annotations

import argparse
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack import cli
from ltl_stack.errors import Exit, OutputError
from ltl_stack.runtime.config.node_params import Bound, NodeConfigError, Param, coerce_param


@settings(max_examples=200, deadline=None)
@given(st.floats(allow_nan=True, allow_infinity=True))
def test_float_options_take_exactly_the_finite_numbers_in_range(x):
    text = repr(x)
    short = abs(x) < 1e18 and (x == 0 or abs(x) >= 1e-9)  # at most 18 digits; not below ROS' nanoseconds
    for parse, ok in ((cli.positive_float, math.isfinite(x) and x > 0 and short),
                      (cli.non_negative_float, math.isfinite(x) and x >= 0 and short)):
        if ok:
            assert parse(text) == x
        else:
            with pytest.raises(argparse.ArgumentTypeError):
                parse(text)


@settings(max_examples=200, deadline=None)
@given(st.integers(min_value=-10**30, max_value=10**30))
def test_int_options_take_integers_in_range_of_at_most_18_digits(n):
    for parse, low in ((cli.non_negative_int, 0), (cli.positive_int, 1)):
        if low <= n < 10**18:
            assert parse(str(n)) == n
        else:
            with pytest.raises(argparse.ArgumentTypeError):
                parse(str(n))


@pytest.mark.parametrize("text", ["nan", "inf", "-inf", "1e999", "abc", "", "7" * 5000, "-1"])
def test_bad_numbers_are_one_short_usage_error(text, capsys):
    parser = cli.ToolParser("t", "d")
    parser.add_argument("--rate", type=cli.positive_float)
    parser.add_argument("--count", type=cli.non_negative_int)
    for option in ("--rate", "--count"):
        with pytest.raises(SystemExit) as done:
            parser.parse_args([option, text])
        assert done.value.code == Exit.BAD_INPUT
        err = capsys.readouterr().err
        errors = [line for line in err.splitlines() if "error:" in line]
        assert len(errors) == 1 and errors[0].startswith(f"t: error: argument {option}: ") and len(errors[0]) < 120, err


def test_write_outputs_writes_all_or_none(tmp_path):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    cli.write_outputs([(a, "one", "first"), (b, b"two", "second")])
    assert (a.read_text(), b.read_text()) == ("one", "two")
    with pytest.raises(OutputError) as err:
        cli.write_outputs([(a, "NEW", "first"), (tmp_path / "no" / "such" / "c.txt", "three", "second")])
    assert err.value.code == Exit.WRITE_FAILED and "c.txt: cannot write the second" in str(err.value)
    assert a.read_text() == "one", "the first output must stay as it was when the second cannot be written"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"], "no temporary file left"


def test_write_outputs_refuses_a_folder_and_leaves_no_temporary_file(tmp_path):
    a = tmp_path / "a.txt"
    with pytest.raises(OutputError, match="it is a directory") as err:
        cli.write_outputs([(a, "one", "first"), (tmp_path, "x", "second")])
    assert err.value.code == Exit.WRITE_FAILED
    assert list(tmp_path.iterdir()) == []


@settings(max_examples=200, deadline=None)
@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(min_value=900, max_value=1100),
                 st.sampled_from([1000.0, 1000.0000001, 0.0, 1e17])))
def test_rates_take_exactly_0_and_1e_9_to_1000_hz_as_option_and_param(x):
    """A rate (``cli.rate_or_zero``, a node's ``Bound.RATE``/``RATE_OR_ZERO`` ``~param``) is finite, at
    most ``MAX_RATE`` (a faster loop only spins a core: ``_rate:=1e17``) and not below ROS'
    nanoseconds; 0 means "off" where the bound allows it."""
    in_range = math.isfinite(x) and 1e-9 <= x <= cli.MAX_RATE
    for ok_zero, parse in ((True, cli.rate_or_zero),
                           (True, lambda t: coerce_param(Param("rate", 1.0, bound=Bound.RATE_OR_ZERO), t, "n")),
                           (False, lambda t: coerce_param(Param("rate", 1.0, bound=Bound.RATE), t, "n"))):
        if in_range or (x == 0 and ok_zero):
            assert parse(repr(x)) == x
        else:
            with pytest.raises((argparse.ArgumentTypeError, NodeConfigError)):
                parse(repr(x))


@settings(max_examples=200, deadline=None)
@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(min_value=0, max_value=0.01),
                 st.sampled_from([0.0, 1e-9, 0.000999, 0.001, 2.0])))
def test_periods_take_exactly_0_and_a_thousandth_of_a_second_or_more(x):
    """A period of something repeated (``Bound.PERIOD_OR_ZERO``: ``~publisher_check_period``,
    ``~ready_timeout``) is 0 (off) or at least 1 / ``MAX_RATE`` s: 1e-9 s accepted before spun a core."""
    param = Param("publisher_check_period", 2.0, bound=Bound.PERIOD_OR_ZERO)
    if x == 0 or (math.isfinite(x) and 1 / cli.MAX_RATE <= x < 1e18):
        assert coerce_param(param, repr(x), "n") == x
    else:
        with pytest.raises(NodeConfigError, match="publisher_check_period"):
            coerce_param(param, repr(x), "n")


def test_every_repeating_period_of_the_executor_has_the_period_bound():
    from ltl_stack.runtime.executor.setup import EXECUTOR_PARAMS

    periods = {p.name: p.bound for p in EXECUTOR_PARAMS if p.name.endswith("period") or "every S seconds" in p.doc}
    assert periods == {"publisher_check_period": Bound.PERIOD_OR_ZERO, "ready_timeout": Bound.PERIOD_OR_ZERO}

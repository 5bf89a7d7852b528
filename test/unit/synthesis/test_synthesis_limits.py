"""One set of synthesis defaults, and the limits of a run: deadline, memory cap (library level)."""
from __future__ import annotations

import argparse
import resource
import warnings

import pytest
from helpers import needs_cudd
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.errors import Exit, UserError
from ltl_stack.spec import parse_slugsin, parse_structured
from ltl_stack.synthesis import (
    DEFAULT_OPTIONS,
    Deadline,
    Game,
    MemoryLimitReached,
    SynthesisOptions,
    TimeLimitReached,
    is_realizable,
    synthesize,
)
from ltl_stack.synthesis import options as options_module
from ltl_stack.synthesis.explain import explain
from ltl_stack.synthesis.options import add_option_flags, memory_cap, options_from, parse_size

COUNTER = "[OUTPUT]\nx:0...65535\n\n[SYS_INIT]\nx = 0\n\n[SYS_TRANS]\nx' = x + 1 | x' = x\n\n[SYS_LIVENESS]\nx = 65535\n"
# unrealizable (a second goal that never holds), found only after the long first goal
STUCK = COUNTER + "FALSE\n"
INIT_ONLY = "[INPUT]\ni\n\n[OUTPUT]\no\n\n[SYS_TRANS]\n! o\n"


def test_the_defaults_are_robotics_semantics_and_cooperative():
    assert (DEFAULT_OPTIONS.robotics_semantics, DEFAULT_OPTIONS.cooperative) == (True, True)
    assert DEFAULT_OPTIONS.describe() == "robotics init semantics, cooperative strategy"
    assert SynthesisOptions(False, False).describe() == "slugs' default init semantics, non-cooperative strategy"
    assert SynthesisOptions(False, True).to_dict() == {"robotics_semantics": False, "cooperative": True}


def test_library_defaults_agree_with_the_options():
    spec = parse_slugsin(INIT_ONLY, "init_only.slugsin")
    result = synthesize(spec)
    assert (result.realizable, result.options) == (False, DEFAULT_OPTIONS), result.options
    assert is_realizable(spec) is False and is_realizable(spec, robotics_semantics=False) is True
    other = synthesize(spec, robotics_semantics=False, cooperative=False)
    assert (other.realizable, other.options) == (True, SynthesisOptions(False, False))
    assert other.strategy.explicit().metadata["robotics_semantics"] is False


@pytest.mark.parametrize("argv, expected", [
    ([], SynthesisOptions(True, True)),
    (["--no-robotics-semantics"], SynthesisOptions(False, True)),
    (["--no-cooperative", "--robotics-semantics"], SynthesisOptions(True, False)),
])
def test_option_flags(argv, expected):
    parser = argparse.ArgumentParser()
    add_option_flags(parser)
    args = parser.parse_args(argv)
    assert options_from(args.robotics_semantics, args.cooperative) == expected


def test_a_timeout_ends_the_fixpoint_with_a_limit_error():
    spec = parse_structured(COUNTER, "counter.structuredslugs")
    with pytest.raises(TimeLimitReached) as info:
        synthesize(spec, timeout=0.3)
    assert info.value.code == Exit.LIMIT and isinstance(info.value, UserError), info.value
    assert "0.3 s" in str(info.value)


def test_a_timeout_ends_explain_too():
    spec = parse_structured(STUCK, "stuck.structuredslugs")
    with pytest.raises(TimeLimitReached):
        explain(spec, deadline=Deadline(0.3))


def test_a_passed_deadline_stops_even_game_construction():
    deadline = Deadline(1e-9)
    with pytest.raises(TimeLimitReached):
        synthesize(parse_slugsin("[INPUT]\ni\n[OUTPUT]\no\n[SYS_TRANS]\n| o' i'\n"), deadline=deadline)


@pytest.mark.parametrize("bad", [0, -1.0, float("nan")])
def test_deadline_needs_a_positive_time(bad):
    with pytest.raises(ValueError):
        Deadline(bad)


@needs_cudd
def test_memory_cap_in_force_from_the_first_clause():
    # a clause whose BDD alone needs more than the cap: no fixpoint runs before the limit
    variables = "\n".join(f"v{k}" for k in range(60))
    clause = " | ".join(f"(v{k} & v{k + 30})" for k in range(30))  # exponential in the declared order
    spec = parse_structured(f"[INPUT]\n{variables}\n[OUTPUT]\no\n[ENV_INIT]\n{clause}\n", "wide.structuredslugs")
    with pytest.raises(MemoryLimitReached) as info:
        synthesize(spec, max_memory=2 * 2**20)
    assert info.value.code == Exit.LIMIT and "2 MiB" in str(info.value), info.value


def test_memory_cap_stays_inside_an_address_space_limit(monkeypatch):
    assert memory_cap(2**30) == 2**30
    monkeypatch.setattr(resource, "getrlimit", lambda _which: (3 * 2**30, resource.RLIM_INFINITY))
    monkeypatch.setattr(options_module, "_address_space_in_use", lambda: 2**30)
    assert memory_cap(8 * 2**30) == 2**30  # half of what is left
    assert memory_cap(2**29) == 2**29


@pytest.mark.parametrize("text, expected", [
    ("512M", 512 * 2**20), ("4G", 4 * 2**30), ("1.5g", 3 * 2**29), ("100000", 100000), ("2MiB", 2 * 2**20),
    ("64k", 64 * 2**10),
])
def test_parse_size(text, expected):
    assert parse_size(text) == expected


@given(st.text(max_size=8))
def test_parse_size_never_crashes(text):
    try:
        assert parse_size(text) > 0
    except ValueError:
        pass


def sum_spec(n: int, total: int) -> str:
    declarations = "\n".join(f"x{k}:0...7" for k in range(n))
    return f"[INPUT]\n{declarations}\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n" + \
        " + ".join(f"x{k}" for k in range(n)) + f" = {total} -> y'\n"


@needs_cudd  # the manager's peak node count
def test_the_bdd_of_a_long_sum_is_built_without_big_intermediate_bdds():
    # the ripple-carry adder's partial sums had BDDs of size O(i^2): millions of peak nodes here
    game = Game(parse_structured(sum_spec(120, 5), "sum.structuredslugs"))
    with warnings.catch_warnings():  # dd warns that the unit of "mem" changed
        warnings.simplefilter("ignore")
        peak = game.bdd.statistics()["peak_nodes"]
    assert peak <= 100 * 3 * 120, peak

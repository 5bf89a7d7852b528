"""``controller_executor --strategy FILE``: a saved automaton runs like the synthesized strategy.

Uses the real synthesizer (``ltl_stack.synthesis``) and the executor's ROS-free helpers.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.errors import Exit
from ltl_stack.runtime.executor.controller import Controller, ViolationPolicy
from ltl_stack.runtime.executor.explicit import AutomatonStrategy
from ltl_stack.runtime.executor.setup import (
    ExecutorError,
    Options,
    build_strategy,
    check_summary,
    merge_options,
    params_lookup,
    parse_init_props,
    prepare,
)
from ltl_stack.spec import parse_slugsin
from ltl_stack.synthesis import synthesize

# out follows a, busy follows lock; the environment promises that lock, once set, stays set.
LOCK = (Path(__file__).resolve().parent / "lock.slugsin").read_text()


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    spec = parse_slugsin(LOCK, "lock.slugsin")
    automaton = synthesize(spec).strategy.explicit()
    path = tmp_path_factory.mktemp("strategy") / "lock.json"
    path.write_text(json.dumps(automaton.to_json()))
    return spec, path


def quiet(_text):
    pass


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.booleans(), st.booleans()), min_size=1, max_size=12))
def test_saved_strategy_gives_the_outputs_the_spec_demands(saved, readings):
    spec, path = saved
    strategy = build_strategy(spec, Options(strategy=str(path)), log=quiet)
    assert isinstance(strategy, AutomatonStrategy)
    ctl = Controller(strategy)
    for a, lock in readings:
        was_locked = ctl.state is not None and ctl.state.inputs["lock"]
        changed = ctl.readings != {"a": a, "lock": lock}
        update = ctl.report_many({"a": a, "lock": lock})
        if ctl.state is None:
            continue
        if was_locked and not lock and changed:
            assert update.violation is not None, update
            assert [c.line for c in update.violation.clauses] == [10], update.violation.clauses
        elif update.stepped:
            assert update.outputs == {"out": a, "busy": lock}, (readings, update)


def test_a_strategy_for_other_propositions_is_refused(saved, tmp_path):
    _, path = saved
    other = parse_slugsin("[INPUT]\nx\n\n[OUTPUT]\ny\n", "other.slugsin")
    with pytest.raises(ExecutorError, match="differ from the spec"):
        build_strategy(other, Options(strategy=str(path)), log=quiet)
    broken = tmp_path / "broken.json"
    broken.write_text("{not json")
    with pytest.raises(ExecutorError, match="broken.json: cannot load strategy"):
        build_strategy(other, Options(strategy=str(broken)), log=quiet)


def test_unrealizable_spec_is_exit_10_from_the_one_table():
    spec = parse_slugsin("[INPUT]\nx\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n& y' ! y'\n", "u.slugsin")
    with pytest.raises(ExecutorError) as info:
        build_strategy(spec, Options(), log=quiet)
    assert info.value.code == Exit.UNREALIZABLE == 10 and "unrealizable" in str(info.value), info.value


def test_synthesis_timeout_is_exit_5(monkeypatch):
    from ltl_stack.synthesis import TimeLimitReached

    def never(*_args, **kwargs):
        assert kwargs["timeout"] == 0.5, kwargs
        raise TimeLimitReached("synthesis stopped after 0.5 s (--timeout)")

    monkeypatch.setattr("ltl_stack.runtime.executor.setup.synthesize", never)
    spec = parse_slugsin(LOCK, "lock.slugsin")
    with pytest.raises(TimeLimitReached) as info:
        build_strategy(spec, merge_options({"timeout": 0.5}), log=quiet)
    assert info.value.code == Exit.LIMIT == 5


def test_cli_flags_win_over_private_params():
    cli = {"robotics_semantics": False, "ready_timeout": 2.0, "rate": None}
    params = {"cooperative": False, "rate": 5.0, "ready_timeout": 9.0, "init_props": {"a": True, "lock": 0},
              "robotics_semantics": True}
    options = merge_options(cli, lambda name: (name in params, params.get(name)))
    assert (options.robotics_semantics, options.cooperative, options.rate, options.ready_timeout) == (
        False, False, 5.0, 2.0), options
    assert options.sources["rate"] == "~rate" and options.sources["ready_timeout"] == "--ready-timeout"
    spec = parse_slugsin(LOCK, "lock.slugsin")
    assert parse_init_props(options.init_props, spec) == {"a": True, "lock": False}
    assert merge_options({}).on_violation is ViolationPolicy.HOLD


def test_private_params_fetched_at_once_are_looked_up_by_name():
    """The node fetches its whole ``~`` namespace in one call (the master's dict, other keys and nested
    values included); merging from it gives what one ``has_param``/``get_param`` per name gave."""
    fetched = {"rate": 5.0, "init_props": {"a": True, "lock": 0}, "not_an_option": 1, "ready_timeout": 9.0}
    options = merge_options({"ready_timeout": 2.0}, params_lookup(fetched))
    assert (options.rate, options.ready_timeout, options.settle_steps) == (5.0, 2.0, merge_options({}).settle_steps)
    assert options.sources["rate"] == "~rate" and options.sources["ready_timeout"] == "--ready-timeout"
    assert options.sources["settle_steps"] == "default"
    spec = parse_slugsin(LOCK, "lock.slugsin")
    assert parse_init_props(options.init_props, spec) == {"a": True, "lock": False}
    assert params_lookup({})("rate") == (False, None)
    assert params_lookup({"rate": None})("rate") == (True, None)
    with pytest.raises(ExecutorError, match="parameter ~settle_steps must be an integer"):
        merge_options({}, params_lookup({"settle_steps": 2.5}))


@pytest.mark.parametrize("name, value, fragment", [
    ("rate", -1.0, "parameter ~rate must be a number >= 0"),
    ("rate", float("nan"), "parameter ~rate must be a number >= 0"),
    ("ready_timeout", float("inf"), "parameter ~ready_timeout must be a number >= 0"),
    ("violation_grace", "soon", "parameter ~violation_grace must be a number"),
    ("settle_steps", 2.5, "parameter ~settle_steps must be an integer"),
    ("settle_steps", float("inf"), "parameter ~settle_steps must be an integer"),
    ("settle_steps", -3, "parameter ~settle_steps must be a number >= 0"),
    ("max_explicit_states", 1e3 + 0.5, "parameter ~max_explicit_states must be an integer"),
    ("init_props", 5, "parameter ~init_props must be a str or dict"),
    ("init_props", {"a": "maybe"}, "~init_props: 'a' needs a true/false value"),
    ("on_violation", "explode", "parameter ~on_violation must be one of hold, all-false"),
    ("namespace", "bad name", "parameter ~namespace must be a legal ROS name"),
    ("cooperative", "perhaps", "parameter ~cooperative must be a bool"),
])
def test_bad_private_params_are_refused_naming_the_param(name, value, fragment):
    with pytest.raises(ExecutorError) as info:
        merge_options({}, lambda n: (n == name, value))
    assert fragment in str(info.value) and info.value.code == Exit.BAD_INPUT, str(info.value)


def test_bad_flag_values_name_the_flag():
    with pytest.raises(ExecutorError, match="--rate must be a number >= 0"):
        merge_options({"rate": float("nan")})


def test_check_with_saved_strategy(saved, tmp_path):
    _, path = saved
    spec_file = tmp_path / "lock.slugsin"
    spec_file.write_text(LOCK)
    options = merge_options({"strategy": str(path), "init_props": "a=0,lock=1"})
    prepared = prepare(str(spec_file), None, options.namespace)
    summary = check_summary(str(spec_file), None, prepared, options, log=quiet)
    assert summary["initial_state"]["outputs"] == {"out": False, "busy": True}, summary
    assert summary["inputs"] == {"a": "/lock/inputs/a", "lock": "/lock/inputs/lock"}, summary

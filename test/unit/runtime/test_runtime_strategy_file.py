"""``controller_executor --strategy FILE``: a saved automaton runs like the synthesized strategy.

Uses the real synthesizer (``ltl_stack.synthesis``) and the executor's ROS-free helpers.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.ros.executor import ExecutorError, Options, _merge_options, build_strategy, parse_init_props
from ltl_stack.runtime.controller import Controller
from ltl_stack.runtime.explicit import AutomatonStrategy
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


def test_unrealizable_spec_is_exit_3():
    spec = parse_slugsin("[INPUT]\nx\n\n[OUTPUT]\ny\n\n[SYS_TRANS]\n& y' ! y'\n", "u.slugsin")
    with pytest.raises(ExecutorError) as info:
        build_strategy(spec, Options(), log=quiet)
    assert info.value.code == 3 and "unrealizable" in str(info.value), info.value


def test_cli_flags_win_over_private_params():
    args = argparse.Namespace(namespace=None, robotics_semantics=False, cooperative=None, strategy=None,
                              init_props=None, rate=None, ready_timeout=2.0, on_violation=None, start_paused=None,
                              publisher_check_period=None)
    params = {"~cooperative": False, "~rate": 5.0, "~ready_timeout": 9.0, "~init_props": {"a": True, "lock": 0},
              "~robotics_semantics": True}
    options = _merge_options(args, lambda name, default: params.get(name, default))
    assert (options.robotics_semantics, options.cooperative, options.rate, options.ready_timeout) == (
        False, False, 5.0, 2.0), options
    spec = parse_slugsin(LOCK, "lock.slugsin")
    assert parse_init_props(options.init_props, spec) == {"a": True, "lock": False}
    with pytest.raises(ExecutorError, match="rate must be a number >= 0"):
        _merge_options(args, lambda name, default: -1.0 if name == "~rate" else default)
    with pytest.raises(ExecutorError, match="on_violation must be one of"):
        _merge_options(args, lambda name, default: "explode" if name == "~on_violation" else default)

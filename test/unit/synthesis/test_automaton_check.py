"""A saved strategy is checked against its spec on load: names, ids, init, safety on every edge."""
from __future__ import annotations

import json
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.errors import Exit
from ltl_stack.runtime.executor.explicit import AutomatonStrategy
from ltl_stack.spec import parse_slugsin
from ltl_stack.synthesis import Automaton, StrategyFileError, synthesize
from ltl_stack.synthesis.automaton_check import check_automaton, load_checked

# out follows a; busy follows lock
V1 = """[INPUT]
a
lock

[OUTPUT]
out
busy

[SYS_TRANS]
! ^ out' a'
! ^ busy' lock'
"""
# the new version: the robot must start idle, and never be busy while out
V2_INIT = V1 + "\n[SYS_INIT]\n! busy\n! out\n"
V2_SAFETY = V1 + "! & out' busy'\n"


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    spec = parse_slugsin(V1, "v1.slugsin")
    automaton = synthesize(spec).strategy.explicit()
    folder = tmp_path_factory.mktemp("strategy")
    path = folder / "v1.json"
    path.write_text(json.dumps(automaton.to_json()))
    slugs = folder / "v1_slugs.json"
    slugs.write_text(json.dumps(automaton.to_slugs_json()))
    return spec, path, slugs


def refusal(path, spec) -> str:
    with pytest.raises(StrategyFileError) as info:
        AutomatonStrategy(Automaton.load(path, inputs=list(spec.inputs)), spec)
    assert info.value.code == Exit.BAD_INPUT
    return str(info.value)


def test_the_strategy_of_the_spec_passes(saved):
    spec, path, slugs = saved
    for file in (path, slugs):
        strategy = AutomatonStrategy(Automaton.load(file, inputs=list(spec.inputs)), spec)
        assert strategy.initial_state() is not None
        assert load_checked(str(file), spec).inputs == spec.inputs


def test_a_strategy_from_an_older_spec_breaking_sys_init_is_refused(saved):
    _, path, _ = saved
    message = refusal(path, parse_slugsin(V2_INIT, "v2.slugsin"))
    assert message.startswith(f"{path}: initial state "), message
    assert re.search(r"breaks sys_init v2\.slugsin:(14: ! busy|15: ! out)$", message), message


def test_an_edge_breaking_sys_safety_is_refused(saved):
    _, path, _ = saved
    message = refusal(path, parse_slugsin(V2_SAFETY, "v2.slugsin"))
    assert f"{path}: edge " in message and "sys_safety v2.slugsin:12: ! & out' busy'" in message, message


def test_an_edge_the_environment_may_not_take_is_refused(saved):
    _, path, _ = saved
    spec = parse_slugsin(V1 + "\n[ENV_TRANS]\n| ! lock lock'\n", "v2.slugsin")
    message = refusal(path, spec)
    assert "does not allow) breaks env_safety v2.slugsin:14" in message, message


def test_recovery_edges_may_break_env_safety():
    spec = parse_slugsin(V1 + "\n[ENV_TRANS]\n| ! lock lock'\n", "v2.slugsin")
    automaton = synthesize(spec).strategy.explicit(recovery=True)
    assert any(s.recovery for s in automaton.states)
    check_automaton(automaton, spec, "recovery.json")


def edited(path, tmp_path, change) -> str:
    data = json.loads(path.read_text())
    change(data)
    out = tmp_path / "edited.json"
    out.write_text(json.dumps(data))
    return str(out)


@pytest.mark.parametrize("change, message", [
    (lambda d: d["states"][0]["successors"].append(999), "has a successor 999 that does not exist"),
    (lambda d: d["initial"].append(777), "initial state 777 does not exist"),
    (lambda d: d["states"][1].update(id=0), "state id 0 is used twice"),
    (lambda d: d["states"][0]["outputs"].pop("busy"), "has no true/false value for busy"),
    (lambda d: d.update(outputs=["out", "idle"]), "are not the spec's"),
    (lambda d: d["states"][0].pop("goal"), "not a usable strategy file: missing field 'goal'"),
    (lambda d: d["states"][0].update(successors="many"), "not a usable strategy file"),
    (lambda d: d.update(format="other"), "neither an ltl_stack-strategy nor a slugs strategy"),
])
def test_broken_files_are_one_error_naming_the_file(saved, tmp_path, change, message):
    spec, path, _ = saved
    file = edited(path, tmp_path, change)
    with pytest.raises(StrategyFileError) as info:
        load_checked(file, spec)
    assert str(info.value).startswith(file) and message in str(info.value), info.value


def test_not_json_is_one_error_naming_file_and_line(tmp_path, saved):
    spec = saved[0]
    bad = tmp_path / "bad.json"
    bad.write_text('{\n"format": ltl}\n')
    with pytest.raises(StrategyFileError, match=r"bad.json:2: invalid JSON"):
        load_checked(str(bad), spec)


values = st.recursive(st.none() | st.booleans() | st.integers(-3, 3) | st.text(max_size=3),
                      lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=3), inner, max_size=3),
                      max_leaves=6)


@settings(max_examples=150, deadline=None)
@given(st.data())
def test_any_edit_loads_or_is_refused_with_one_error(saved, tmp_path_factory, data):
    spec, path, _ = saved
    document = json.loads(path.read_text())
    state = data.draw(st.integers(0, len(document["states"]) - 1))
    key = data.draw(st.sampled_from(["id", "goal", "inputs", "outputs", "successors", "recovery"]))
    document["states"][state][key] = data.draw(values)
    file = tmp_path_factory.mktemp("edit") / "edit.json"
    file.write_text(json.dumps(document))
    try:
        load_checked(str(file), spec)
    except StrategyFileError as e:
        assert str(e).startswith(str(file)), e

"""Where the BDDs are dd's pure-Python ones (Python 3.8: no CUDD wheel), the suite runs fewer Hypothesis
examples and skips the tests that solve large games, saying why (test/conftest.py); with CUDD it runs
every example and every test."""
from __future__ import annotations

import pytest
from helpers import BDD_BACKEND, HEAVY_GAME_REASON, heavy_game
from hypothesis import given, settings
from hypothesis import strategies as st

#: what the property below asks for, above the pure-Python dd profile's count
OWN_EXAMPLES = 50


@settings(max_examples=OWN_EXAMPLES, deadline=None)
@given(st.integers())
def test_a_property_with_its_own_number_of_examples(value):
    assert isinstance(value, int)


@heavy_game
def test_a_heavy_game_test_runs_with_cudd():
    assert BDD_BACKEND == "cudd"


def _item(request: pytest.FixtureRequest, name: str) -> pytest.Item:
    return next(i for i in request.session.items if i.name == name)


def test_the_number_of_examples_follows_the_bdd_backend(request):
    own = _item(request, "test_a_property_with_its_own_number_of_examples").obj._hypothesis_internal_use_settings
    if BDD_BACKEND == "cudd":
        assert own.max_examples == OWN_EXAMPLES
    else:
        cap = settings.get_profile("suite_pure_python_dd").max_examples
        assert settings.default is settings.get_profile("suite_pure_python_dd")
        assert own.max_examples == cap < OWN_EXAMPLES
        assert own.derandomize and own.deadline is None  # the rest of its settings kept


def test_heavy_games_are_skipped_only_on_pure_python_dd(request):
    skips = [m for m in _item(request, "test_a_heavy_game_test_runs_with_cudd").iter_markers("skip")]
    if BDD_BACKEND == "cudd":
        assert skips == []
    else:
        assert [m.kwargs["reason"] for m in skips] == [HEAVY_GAME_REASON]
        assert "pure-Python dd" in HEAVY_GAME_REASON

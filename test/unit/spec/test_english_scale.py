"""n regions give O(n) clauses and formula nodes (600 declared regions made 360,000
clauses). Work is counted, never timed."""
from __future__ import annotations

import json

import pytest
from english_testing import CONFIG, Bdds

from ltl_stack.spec import activation_completion
from ltl_stack.spec.activation_completion import at_most_one, exactly_one
from ltl_stack.spec.english_files import parse_english
from ltl_stack.spec.formula import children
from ltl_stack.synthesis import is_realizable

SECTIONS = ("env_init", "sys_init", "env_safety", "sys_safety", "env_liveness", "sys_liveness")


def _size(spec) -> tuple[int, int]:
    clauses = [c.formula for s in SECTIONS for c in spec.section(s)]
    seen: set[int] = set()
    stack = list(clauses)
    while stack:
        f = stack.pop()
        if id(f) not in seen:
            seen.add(id(f))
            stack.extend(children(f))
    return len(clauses), len(seen)


def _declared(n: int):
    return parse_english("Sensors: s\nRegions: " + ", ".join(f"r{i}" for i in range(n)) + "\nvisit r0\n", "d.spec")


def _grid(n: int, tmp_path):
    w = int(n ** 0.5)
    cells = [{"name": "boundary", "type": "rect", "position": [0, 0], "size": [10 * w, 10 * w]}]
    cells += [{"name": f"r{i}", "type": "rect", "position": [10 * (i % w), 10 * (i // w)], "size": [10, 10]}
              for i in range(w * w)]
    (tmp_path / f"g{n}.regions").write_text("Regions:\n" + json.dumps(cells) + "\n")
    return parse_english(f"Sensors: s\nMap: g{n}.regions\nvisit r0\n", str(tmp_path / "g.spec"))


@pytest.mark.parametrize("build", ["declared", "grid"])
def test_clauses_and_formula_nodes_grow_linearly(build, tmp_path):
    make = _declared if build == "declared" else (lambda n: _grid(n, tmp_path))
    small_clauses, small_nodes = _size(make(100))
    big_clauses, big_nodes = _size(make(400))
    assert big_clauses <= 4.2 * small_clauses
    assert big_nodes <= 4.2 * small_nodes  # quadratic would be 16x
    assert big_nodes < 100 * 400


@pytest.mark.parametrize("n", [2, 3, 5, 8, 17])
def test_linear_encodings_mean_the_expanded_ones(n, monkeypatch):
    names = [f"x{i}" for i in range(n)]
    bdds = Bdds(names)
    expanded = (bdds.of(exactly_one(names, True)), bdds.of(at_most_one(names, False)))
    monkeypatch.setattr(activation_completion, "LINEAR_FROM", 2)
    assert (bdds.of(exactly_one(names, True)), bdds.of(at_most_one(names, False))) == expanded


def test_linear_region_clauses_keep_the_verdicts(monkeypatch):
    text = (CONFIG / "clean_and_patrol" / "clean_and_patrol.spec").read_text()
    base = str(CONFIG / "clean_and_patrol" / "clean_and_patrol.spec")
    expanded = parse_english(text, base)
    monkeypatch.setattr(activation_completion, "LINEAR_FROM", 2)
    linear = parse_english(text, base)
    assert _size(linear)[1] != _size(expanded)[1]  # the linear forms are in use
    assert is_realizable(linear) and is_realizable(expanded)
    broken = text.replace("Start in topLane.", "Start in topLane.\nAlways not rightGround.")
    assert not is_realizable(parse_english(broken, base))

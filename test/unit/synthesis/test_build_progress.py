"""Building a large game's BDDs reports progress (a multiplier-like circuit printed nothing for
minutes): a line once ``build_progress.EVERY`` BDD operations and ``INTERVAL`` seconds passed. Lines are counted, never timed
(the interval between lines is set to 0 here)."""
from __future__ import annotations

import pytest

from ltl_stack.spec import parse_structured
from ltl_stack.synthesis import build_progress, synthesize
from ltl_stack.synthesis.game import Game


def _product_table(n: int) -> str:
    """Every partial product of an n-bit multiplier as an output: n*n assignments."""
    inputs = [f"a{i}" for i in range(n)] + [f"b{i}" for i in range(n)]
    outputs = [f"p{i}_{j}" for i in range(n) for j in range(n)]
    trans = [f"p{i}_{j}' <-> (a{i}' & b{j}')" for i in range(n) for j in range(n)]
    return "\n".join(["[INPUT]", *inputs, "[OUTPUT]", *outputs, "[SYS_TRANS]", *trans, ""])


@pytest.fixture
def every_10(monkeypatch):
    monkeypatch.setattr(build_progress, "EVERY", 10)
    monkeypatch.setattr(build_progress, "INTERVAL", 0.0)


def test_building_a_large_game_reports_every_so_many_operations(every_10):
    lines: list[str] = []
    game = Game(parse_structured(_product_table(8)), progress=lines.append)
    building = [line for line in lines if line.startswith("building the BDDs")]
    assert len(building) >= 3, lines
    assert "sys_safety line" in building[0], building[0]
    assert game._building is None  # nothing is reported once the game is built
    assert len(lines) == len(building), lines


def test_synthesize_passes_its_progress_to_the_construction(every_10):
    lines: list[str] = []
    synthesize(parse_structured(_product_table(4)), progress=lines.append, strategy=False)
    assert any(line.startswith("building the BDDs") for line in lines), lines


def test_fewer_operations_than_every_report_nothing(monkeypatch):
    monkeypatch.setattr(build_progress, "EVERY", 10**6)
    monkeypatch.setattr(build_progress, "INTERVAL", 0.0)
    lines: list[str] = []
    Game(parse_structured(_product_table(4)), progress=lines.append)
    assert lines == []


def test_lines_are_one_per_every_operations():
    lines: list[str] = []
    reporter = build_progress.BuildProgress(lines.append, 10, every=7, interval=0.0)
    for _ in range(50):
        reporter.tick()
    assert len(lines) == 50 // 7, lines
    assert lines[-1].endswith("(0/10 clauses, 49 BDD operations)"), lines[-1]


def test_lines_are_at_least_interval_apart():
    now = [0.0]
    lines: list[str] = []
    reporter = build_progress.BuildProgress(lines.append, 1, every=1, interval=5.0, clock=lambda: now[0])
    for step in range(20):
        now[0] = step  # one second per operation: a line every 5 operations, not every one
        reporter.tick()
    assert len(lines) == 3, lines

"""The adaptive dynamic-reordering policy of ``fixpoint.solve``: a game that is already
big after construction starts its fixpoint without reordering, a small one reorders from a small
threshold; the verdicts never depend on it, on every shared spec and a few generated members."""
from __future__ import annotations

import warnings

import pytest
from helpers import heavy_game, needs_cudd, require_shared, shared_dir

from ltl_stack.spec import load_spec
from ltl_stack.synthesis import Game, Options
from ltl_stack.synthesis.fixpoint import reorder_threshold, solve
from ltl_stack.synthesis.game import BIG_GAME, BIG_GAME_GROWTH, REORDER_THRESHOLD

GENERATED = ["factory_assembly_4x3_1_1errors", "factory_assembly_5x3_1_0errors", "factory_assembly_5x3_1_5errors",
             "moving_obstacle_8x8_0glitches", "moving_obstacle_8x8_1glitches", "cinderella_stepmother_n5c2_6_by_4",
             "cinderella_stepmother_n5c2_7_by_4"]


def shared_slugsin() -> list[str]:
    base = shared_dir()
    if base is None:
        return []
    found = sorted(base.glob("specs/*/*.slugsin")) + sorted(base.glob("specs/benchmarks/slugsin/*.slugsin"))
    found += [base / "specs" / "benchmarks" / "generated" / f"{g}.slugsin" for g in GENERATED]
    return [str(p.relative_to(base)) for p in found if p.stem != "basicEvasion"]  # basicEvasion: ~30 s


#: its four solutions took over 600 s on pure-Python dd under load (docs/python_versions.md)
HEAVY = "factory_assembly_5x3_1_5errors"


def cases() -> list:
    return [pytest.param(p, marks=heavy_game) if HEAVY in p else p for p in shared_slugsin()]


def reorderings(game: Game) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # dd warns that one unrelated key changed its unit
        return int(game.bdd.statistics()["n_reorderings"])


@pytest.mark.parametrize("path", cases())
def test_verdicts_do_not_depend_on_the_reordering_policy(path: str) -> None:
    spec = load_spec(require_shared(*path.split("/")))
    verdicts = set()
    for options in (Options(), Options(big_game=0)):  # as the game is; every game treated as big
        for robotics in (False, True):
            verdicts.add((robotics, solve(Game(spec), robotics_semantics=robotics, options=options).realizable))
    assert len(verdicts) == 2, verdicts  # one verdict per semantics


def test_the_threshold_follows_the_size_of_the_built_game() -> None:
    spec = load_spec(require_shared("specs", "benchmarks", "generated", "moving_obstacle_8x8_0glitches.slugsin"))
    game = Game(spec)
    assert 0 < game.nodes < BIG_GAME
    assert reorder_threshold(game, Options()) == REORDER_THRESHOLD
    big = Options(big_game=game.nodes)  # as if this game were big
    assert reorder_threshold(game, big) == max(REORDER_THRESHOLD, int(BIG_GAME_GROWTH * game.nodes))


@needs_cudd
def test_a_big_game_starts_its_fixpoint_without_reordering() -> None:
    # moving_obstacle 16x16: a small game whose fixpoint grows ~20x; as a small game it sifts during
    # the fixpoint, treated as a big one (growth factor out of reach) it does not
    spec = load_spec(require_shared("specs", "benchmarks", "generated", "moving_obstacle_16x16_3glitches.slugsin"))
    counts = {}
    for label, options in (("small", Options()), ("big", Options(big_game=0, big_game_growth=10**6))):
        game = Game(spec)
        before, setting = reorderings(game), game.bdd.configure()["reordering"]
        counts[label] = (solve(game, options=options).realizable, reorderings(game) - before)
        assert game.bdd.configure()["reordering"] is setting  # the manager's setting is restored on return
    assert counts["small"][0] is counts["big"][0] is True
    assert counts["small"][1] > 0 and counts["big"][1] == 0, counts

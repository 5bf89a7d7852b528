"""Lemma 1(a) in every executor configuration: whatever the mode and phase — normal,
recovering, holding, characterizing, waiting for the user, right after a resynthesis or an adopted
spec — every output valuation the controller publishes keeps the system safety rho_s whenever some
valuation does. In process, as the node builds it (``build_strategy`` + ``make_controller``), no ROS.

The oracle evaluates the generated rho_s clauses itself (Python, not BDDs). Generated rho_s clauses
speak of next-state variables (judged from the current readings alone, also after settling steps,
which publish only the last state of a chain of moves) and of current and next outputs (``x -> y'``):
those the valuations a policy publishes (holding, characterizing, waiting for the user) must keep
for the move the robot made, from the position last published (readings then, outputs published).
"""
from __future__ import annotations

import itertools

from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from queued_jobs import Jobs

from ltl_stack.runtime.executor.output_guard import nearest_safe_outputs
from ltl_stack.runtime.executor.setup import build_strategy, make_controller, merge_options
from ltl_stack.runtime.resilience.characterize import Observation
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience
from ltl_stack.spec import parse_structured
from ltl_stack.synthesis import synthesize
from ltl_stack.synthesis.game import Game

INPUTS = ["a", "b"]
OUTPUTS = ["x", "y", "z"]
# rho_s templates: (text, python check on the position before ``w`` and the next valuation ``v``)
SYS = [("{i}' -> {o}'", lambda w, v, i, o, p: not v[i] or v[o]),
       ("{o}' -> {i}'", lambda w, v, i, o, p: not v[o] or v[i]),
       ("{i}' -> !{o}'", lambda w, v, i, o, p: not v[i] or not v[o]),
       ("!({o}' & {p}')", lambda w, v, i, o, p: not (v[o] and v[p])),
       # over current and next outputs: consecutive outputs tied together
       ("{o} -> {p}'", lambda w, v, i, o, p: not w[o] or v[p]),
       ("{o} & {i}' -> {o}'", lambda w, v, i, o, p: not (w[o] and v[i]) or v[o]),
       ("!{o} -> !{p}'", lambda w, v, i, o, p: w[o] or not v[p])]
#: the templates that speak of next-state variables only
NEXT_ONLY = {SYS[k][0] for k in range(4)}
ENV = ["a'", "!a' | !b'", "a' -> a", "b' -> !a'", "a' | b'"]


@st.composite
def specs(draw):
    clauses = []
    for _ in range(draw(st.integers(1, 3))):
        k = draw(st.integers(0, len(SYS) - 1))
        i = draw(st.sampled_from(INPUTS))
        o, p = draw(st.permutations(OUTPUTS))[:2]
        clauses.append((SYS[k][0].format(i=i, o=o, p=p), SYS[k][1], i, o, p, SYS[k][0] in NEXT_ONLY))
    env = draw(st.lists(st.sampled_from(ENV), min_size=1, max_size=2, unique=True))
    goal = draw(st.sampled_from(["", "x", "!x", "y | a"]))
    text = ("[INPUT]\na\nb\n\n[OUTPUT]\nx\ny\nz\n\n[ENV_INIT]\na\n!b\n\n[SYS_INIT]\n!x\n!y\n!z\n\n"
            "[ENV_TRANS]\n" + "\n".join(env)
            + "\n\n[SYS_TRANS]\n" + "\n".join(c[0] for c in clauses) + "\n"
            + (f"\n[SYS_LIVENESS]\n{goal}\n" if goal else ""))
    return text, clauses


def keeps(clauses, valuation, before=None) -> bool:
    """``valuation`` keeps the clauses for the move from ``before`` (None: the next-only clauses)."""
    return all(check(before, valuation, i, o, p) for _text, check, i, o, p, next_only in clauses
               if next_only or before is not None)


MODES = [  # (name, options): every executor configuration
    ("recovery (default)", {}),
    ("recovery, all-false", {"on_violation": "all-false"}),
    ("recovery, symbolic", {"max_explicit_states": 0}),
    ("hold (--no-recovery)", {"recovery": False}),
    ("all-false (--no-recovery)", {"recovery": False, "on_violation": "all-false"}),
    ("hold, symbolic", {"recovery": False, "max_explicit_states": 0, "settle_steps": 0}),
    ("EC only (--no-recovery --characterize)", {"recovery": False, "characterize": True}),
    ("EC only, all-false", {"recovery": False, "characterize": True, "on_violation": "all-false"}),
    ("EC with recovery", {"characterize": True}),
    ("EC with recovery after 2 transitions", {"characterize": True, "characterize_after_transitions": 2}),
]
VALUATIONS = [dict(zip(INPUTS, bits)) for bits in itertools.product([False, True], repeat=2)]
OPS = st.one_of(st.tuples(st.just("inputs"), st.sampled_from(VALUATIONS)),
                st.tuples(st.just("inputs"), st.sampled_from(VALUATIONS)),
                st.tuples(st.just("jobs")), st.tuples(st.just("tick")), st.tuples(st.just("user")),
                st.tuples(st.just("adopt")),
                # inputs going stale (older than their freshness bound) and fresh again
                st.tuples(st.just("stale"), st.sampled_from([(), ("a",), ("b",), ("a", "b")])))


CHECKED: list = []  # the runs that got past ``assume`` (the test checks there are many)


def check_run(text, clauses, options, ops) -> None:
    spec = parse_structured(text, "prop.structuredslugs")
    opts = merge_options(options)
    assume(synthesize(spec).realizable)
    CHECKED.append(options)
    strategy = build_strategy(spec, opts, log=lambda _t: None)
    controller = make_controller(strategy, opts, {})
    jobs = Jobs()
    world = []  # the distinct positions (readings and outputs published) the robot went through

    class Published(list):
        def append(self, update) -> None:
            super().append(update)
            position = {**controller.readings, **update.outputs}
            if not world or world[-1] != position:
                world.append(position)

    published = Published()
    if isinstance(strategy, BackgroundResilience):
        strategy.runner = jobs
        strategy.on_installed = lambda state: published.append(controller.restart_from(state))
    published.append(controller.report_many({"a": True, "b": False}))
    first = controller.state  # the initial state keeps the init sections; rho_s is about moves
    for op in ops:
        moves = len(world)
        if op[0] == "inputs":
            published.append(controller.report_many(op[1]))
        elif op[0] == "tick":
            published.append(controller.tick())
        elif op[0] == "jobs":
            jobs.run_all()
        elif op[0] == "stale":
            published.append(controller.set_unknown(op[1]))
        elif op[0] == "user" and isinstance(strategy, BackgroundResilience) and strategy.job is None:
            try:
                strategy.add_env_liveness("a | !a")
            except Exception:  # noqa: BLE001 - refused or aborted: the outputs are what is checked
                pass
        elif op[0] == "adopt" and isinstance(strategy, BackgroundResilience) and controller.state is not None:
            # negotiation's adoption (Alg. 4): a spec whose init is the current position, put in place
            state = controller.state
            seen = Observation(0, 0.0, dict(state.inputs), dict(state.outputs), controller.readings)
            agreed_text = strategy.characterizer.text(None, seen)
            agreed = strategy.characterizer.parse(agreed_text)
            result = synthesize(agreed)
            if result.realizable:
                with controller.lock:
                    adopted = strategy.adopt(agreed, agreed_text, result.strategy, controller.readings, state.outputs)
                    published.append(controller.restart_from(adopted))
        if (controller.aborted is not None or controller.state is None or not controller.running
                or (controller.state is first and controller.violation is None)):
            continue  # abort (Alg. 3 line 11) and the time before the start: every output false
        readings = controller.readings
        outputs = controller.current_outputs()
        possible = any(keeps(clauses, {**readings, **dict(zip(OUTPUTS, bits))})
                       for bits in itertools.product([False, True], repeat=len(OUTPUTS)))
        if possible:
            assert keeps(clauses, {**readings, **outputs}), (op, readings, outputs, controller.violation)
            assert keeps(clauses, {**readings, **published[-1].outputs}), (op, readings, published[-1])
        if controller.unknown and len(world) >= 2 and len(world) > moves:
            check_unknown(clauses, controller, world, op)
            continue
        if controller.violation is None or len(world) == moves or len(world) < 2:
            continue  # a strategy move (kept by construction), or nothing new published
        before = world[-2]  # the policy's valuation: a move from the position published before
        possible = any(keeps(clauses, {**readings, **{o: bits[k] for k, o in enumerate(OUTPUTS)}}, before)
                       for bits in itertools.product([False, True], repeat=len(OUTPUTS)))
        if possible:
            assert keeps(clauses, world[-1], before), (op, before, world[-1])
            assert keeps(clauses, {**readings, **outputs}, before), (op, before, outputs)


def check_unknown(clauses, controller, world, op) -> None:
    """With inputs unknown, the published valuation keeps every clause for every value of them
    (from the position published before) when some valuation does, else every output is false."""
    before, now = world[-2], world[-1]
    unknown = controller.unknown
    values = [dict(zip(unknown, bits)) for bits in itertools.product([False, True], repeat=len(unknown))]  # noqa: B905

    def safe(outputs) -> bool:
        return all(keeps(clauses, {**now, **v, **outputs}, before) for v in values)

    some = any(safe({o: bits[k] for k, o in enumerate(OUTPUTS)})
               for bits in itertools.product([False, True], repeat=len(OUTPUTS)))
    outputs = {o: now[o] for o in OUTPUTS}
    if some:
        assert safe(outputs), (op, before, now, unknown)
    else:
        assert not any(outputs.values()), (op, before, now, unknown)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(specs(), st.sampled_from(MODES), st.lists(OPS, min_size=1, max_size=12))
@example(("[INPUT]\na\nb\n\n[OUTPUT]\nx\ny\nz\n\n[ENV_INIT]\na\n!b\n\n[SYS_INIT]\n!x\n\n[ENV_TRANS]\na'\n\n[SYS_TRANS]\nb' -> x'\n",
          [("b' -> x'", SYS[0][1], "b", "x", "y", True)]),
         MODES[6], [("inputs", {"a": False, "b": True}), ("inputs", {"a": False, "b": True})])
@example(("[INPUT]\na\nb\n\n[OUTPUT]\nx\ny\nz\n\n[ENV_INIT]\na\n!b\n\n[SYS_INIT]\n!x\n\n[ENV_TRANS]\na'\n\n[SYS_TRANS]\nb' -> x'\n",
          [("b' -> x'", SYS[0][1], "b", "x", "y", True)]),
         MODES[3], [("inputs", {"a": False, "b": True})])
@example(("[INPUT]\na\nb\n\n[OUTPUT]\nx\ny\nz\n\n[ENV_INIT]\na\n!b\n\n[SYS_INIT]\n!x\n!y\n\n[ENV_TRANS]\na'\n\n"
          "[SYS_TRANS]\nb' -> x'\nx -> y'\n",
          [("b' -> x'", SYS[0][1], "b", "x", "y", True), ("x -> y'", SYS[4][1], "b", "x", "y", False)]),
         MODES[3], [("inputs", {"a": False, "b": True}), ("inputs", {"a": False, "b": False})])
@example(("[INPUT]\na\nb\n\n[OUTPUT]\nx\ny\nz\n\n[ENV_INIT]\na\n!b\n\n[SYS_INIT]\n!x\n!y\n\n[ENV_TRANS]\na'\n\n"
          "[SYS_TRANS]\nb' -> x'\nx -> y'\n",
          [("b' -> x'", SYS[0][1], "b", "x", "y", True), ("x -> y'", SYS[4][1], "b", "x", "y", False)]),
         MODES[4], [("inputs", {"a": False, "b": True}), ("inputs", {"a": False, "b": False})])
def test_every_published_valuation_keeps_rho_s_when_one_can(spec_and_clauses, mode, ops):
    text, clauses = spec_and_clauses
    check_run(text, clauses, mode[1], ops)


def test_the_property_test_checks_many_runs():
    """Runs after the property test (same module, in file order): most generated specs were realizable."""
    if CHECKED:  # the property test ran in this process
        assert len(CHECKED) >= 60


def test_nearest_safe_outputs_changes_fewest_outputs_and_names_clauses_when_none_is_safe():
    spec = parse_structured("[INPUT]\np\n\n[OUTPUT]\nx\ny\nz\n\n[SYS_TRANS]\np' -> x'\np' -> !y'\n"
                            "x' & z' -> FALSE\n", "n.structuredslugs")
    game = Game(spec)
    here = {"p": False, "x": False, "y": False, "z": False}
    got = nearest_safe_outputs(game, here, {"p": True}, {"x": False, "y": True, "z": True})
    assert got.outputs == {"x": True, "y": False, "z": False} and got.safe  # 3 changes: the only safe one
    kept = nearest_safe_outputs(game, here, {"p": False}, {"x": False, "y": True, "z": True})
    assert kept.outputs == {"x": False, "y": True, "z": True}  # already safe: held as it is
    fewest = nearest_safe_outputs(game, here, {"p": True}, dict.fromkeys("xyz", False))
    assert fewest.outputs == {"x": True, "y": False, "z": False}
    stuck = parse_structured("[INPUT]\np\n\n[OUTPUT]\nx\n\n[SYS_TRANS]\np' -> x'\np' -> !x'\n", "s.structuredslugs")
    none = nearest_safe_outputs(Game(stuck), {"p": False, "x": False}, {"p": True}, {"x": False})
    assert not none.safe and none.outputs == {"x": False}
    assert {c.location for c in none.unkeepable} == {"s.structuredslugs:8", "s.structuredslugs:9"}

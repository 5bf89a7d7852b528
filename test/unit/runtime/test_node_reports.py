"""The executor node's decisions in the pure layer (``runtime.executor.node_reports.NodeReports``, testable without ROS):
what one controller update publishes, the counters, the mode, health and violation reports, the
publisher warnings. In process, as the node builds its controller (``build_strategy`` +
``make_controller``), no ROS. The texts are the node's (docs/executor.md, docs/resilience.md)."""
from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.runtime.executor.node_reports import ERROR, MODE_LEVELS, OK, WARN, NodeReports, step_report
from ltl_stack.runtime.executor.setup import build_strategy, make_controller, merge_options
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience
from ltl_stack.spec import parse_structured

# the person/door probe of test_executor_recovery
SPEC = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\npass\n\n[ENV_INIT]\ndoor\n\n[SYS_INIT]\n!pass\n\n" \
       "[ENV_TRANS]\ndoor'\n\n[SYS_TRANS]\nperson' -> stop'\npass' -> door'\n\n[SYS_LIVENESS]\npass\n"
TOPICS = {"person": "/probe/inputs/person", "door": "/probe/inputs/door"}
DOOR = "probe.structuredslugs:16: door'"


def node(ready_timeout: float = 10.0, **options):
    """A controller as the node builds it and its reports (``options`` as in ``merge_options``)."""
    opts = merge_options(options)
    spec = parse_structured(SPEC, "probe.structuredslugs")
    strategy = build_strategy(spec, opts, log=lambda _t: None)
    controller = make_controller(strategy, opts, {})
    if isinstance(strategy, BackgroundResilience):
        strategy.runner = lambda job: None  # the resynthesis never runs: the node stays characterizing
    return controller, NodeReports(controller, opts.on_violation.value, opts.recovery, TOPICS, ready_timeout)


def test_hold_violation_is_counted_reported_once_and_cleared_once():
    controller, reports = node(recovery=False)
    first = reports.publication(controller.report_many({"person": False, "door": True}), force_state=True)
    assert first.state and first.step and first.health and first.mode and not first.violation
    assert reports.mode_report().status.message == "normal" and reports.mode == "normal"
    held = reports.publication(controller.report_many({"person": True, "door": False}))
    assert held.violation and held.state and held.mode and not held.step and held.result is None
    assert reports.current_mode() == "holding" and reports.counters.violations == 1
    report = reports.violation(held.update, held.result)
    assert report.level == ERROR and DOOR in report.text and "holding the last outputs" in report.text
    assert reports.violation(held.update, held.result) is None  # the same readings: reported once
    mode = reports.mode_report()
    assert mode.changed and mode.status.level == WARN and mode.event["mode"] == "holding"
    assert mode.status.message == ("holding: no recovery move; outputs by --on-violation hold, kept safe "
                                   f"(Lemma 1(a)); violated: {DOOR} (always next door)"), mode.status.message
    assert ("violated_clause", f"{DOOR} (always next door)") in mode.status.values
    assert ("violations", "1") in mode.status.values and mode.spec_file is None
    back = reports.publication(controller.report_many({"person": True, "door": True}))
    assert back.cleared is not None and back.cleared.message == "inputs admissible again"
    assert back.cleared.level == OK and not back.cleared.quiet
    assert reports.publication(controller.report_many({"person": False, "door": True})).cleared is None
    assert reports.current_mode() == "normal" and reports.violated_clauses() == []


def test_recovery_move_is_a_warn_and_counts_a_recovery_step():
    controller, reports = node()
    reports.publication(controller.report_many({"person": False, "door": True}))
    moved = reports.publication(controller.report_many({"person": True, "door": False}))
    assert moved.violation and moved.update.recovered and moved.result is not None
    assert reports.counters.recovery_steps == 1 and reports.current_mode() == "recovering"
    report = reports.violation(moved.update, moved.result)
    assert report.level == WARN and f"recovering ({moved.result.kind.value})" in report.text
    assert reports.mode_report().status.message.startswith("recovering: recovery moves keep the system safety")


def test_characterizing_then_aborted_mode_and_the_spec_file_status(tmp_path):
    path = tmp_path / "characterized.structuredslugs"
    controller, reports = node(recovery=False, characterized_spec=str(path))
    reports.publication(controller.report_many({"person": False, "door": True}))
    reports.publication(controller.report_many({"person": True, "door": False}))
    mode = reports.mode_report()
    assert mode.mode == "characterizing" and mode.status.level == WARN
    assert mode.status.message.startswith("characterizing: resynthesizing (holding meanwhile, kept safe)")
    assert mode.status.message.endswith("; resyntheses 0 (EC1 0, EC2 0, user 0, negotiated 0); negotiations 0")
    assert mode.spec_file.level == OK and mode.spec_file.message == f"{path}: written after each new strategy"
    reports.resilient.write_error = f"{path}: cannot write"
    assert reports.mode_report().spec_file.level == ERROR
    controller.abort("aborted by the user (~abort)")
    aborted = reports.mode_report()
    assert aborted.status.level == ERROR and aborted.changed
    assert aborted.status.message.startswith("aborted (aborted by the user (~abort)): every output is false")
    assert aborted.event == {"event": "mode", "mode": "aborted", "resyntheses": 0, "ec1": 0, "ec2": 0, "user": 0,
                            "negotiated": 0, "negotiations": 0}


def test_health_before_the_inputs_paused_and_running():
    controller, reports = node(ready_timeout=10.0)
    inputs, state = reports.health(waited=3.0)
    assert (inputs.level, inputs.message) == (OK, "waiting for input(s) person, door")
    assert ("topics", "/probe/inputs/person, /probe/inputs/door") in inputs.values
    assert state.message == "waiting for every input to report" and not state.quiet
    assert reports.health(waited=10.0)[0].level == WARN
    assert reports.silent_inputs(12.0) == (
        "no message after 12 s from input(s) person (/probe/inputs/person), door (/probe/inputs/door); not "
        "stepping until every input has reported once — is each input proposition node running?")
    update = controller.report_many({"person": False, "door": True})
    inputs, state = reports.health(waited=12.0)
    assert inputs.quiet and state.quiet and state.message == f"running: state {update.state.id}, goal 1"
    assert reports.silent_inputs(12.0) is None
    controller.set_running(False)
    assert reports.health(12.0)[1].message == "paused: every output is false"
    assert step_report(update)[0].startswith(f"initial state {update.state.id} (goal 1): inputs ")


def test_a_second_publisher_is_warned_about_once():
    _controller, reports = node()
    two = {"/probe/inputs/person": ("/a", "/b")}
    issued, status = reports.publishers(two)
    assert issued == ["input 'person': topic /probe/inputs/person has 2 publishers (/a, /b); an input topic "
                      "should have exactly one input proposition node (thesis 3.5.1)"]
    assert status.level == WARN and not status.quiet
    issued, status = reports.publishers(two)
    assert issued == [] and status.level == WARN and status.quiet
    issued, status = reports.publishers({})
    assert issued == [] and status.level == OK and status.quiet


READINGS = st.sampled_from([{"person": p, "door": d} for p in (False, True) for d in (False, True)])


@settings(max_examples=60)
@given(st.sampled_from([{"recovery": False}, {}, {"recovery": False, "on_violation": "all-false"}]),
       st.lists(READINGS, min_size=1, max_size=12))
def test_every_violation_counted_once_and_the_mode_level_follows_the_mode(options, sequence):
    """Invariants: the node's own counters count every update that carried a violation, a violation
    is reported once per distinct readings until the inputs are admissible again, and each mode has
    its level."""
    controller, reports = node(**options)
    violations = reported = 0
    last = None
    for readings in sequence:
        publication = reports.publication(controller.report_many(readings))
        if publication.violation:
            violations += 1
            report = reports.violation(publication.update, publication.result)
            key = tuple(sorted(readings.items()))
            assert (report is None) == (key == last)
            reported += report is not None
            last = key
        elif publication.cleared is not None:
            last = None  # admissible again: the next violation is a new one
        mode = reports.mode_report()
        assert mode.status.level == MODE_LEVELS[mode.mode]
        assert (mode.mode == "holding") == (controller.violation is not None)
    assert reports.counters.violations == violations >= reported


def test_add_env_liveness_answers_by_mode_and_abort_is_refused_once_aborted(tmp_path):
    """``~add_env_liveness``: a bad formula is exit 2 (a warning to log), outside the wait for the
    user exit 1 (nothing logged), while waiting it resynthesizes (exit 0, written to the path);
    ``~abort`` on an aborted node is refused."""
    from ltl_stack.errors import Exit

    path = tmp_path / "ch.structuredslugs"
    controller, reports = node(recovery=False, characterized_spec=str(path))
    reports.resilient.runner = lambda job: job()  # the resynthesis at once, in this thread
    reports.resilient.on_installed = controller.restart_from
    bad = reports.add_env_liveness("[ENV_TRANS]", str(path))
    assert (bad.success, bad.code, bad.log[0]) == (False, Exit.BAD_INPUT, "warn") and "section header" in bad.message
    early = reports.add_env_liveness("door", str(path))
    assert (early.code, early.log) == (Exit.NEGATIVE, None) and early.message.startswith("not ready")
    for readings in ({"person": False, "door": True}, {"person": False, "door": False},
                     {"person": True, "door": False}):
        reports.publication(controller.report_many(readings))
    assert reports.current_mode() == "waiting_for_user", reports.resilient.events
    answer = reports.add_env_liveness("door", str(path))
    assert (answer.success, answer.code, answer.log[0]) == (True, Exit.OK, "info"), answer
    assert answer.message == f"realizable with 'door' (EC1); running the new strategy; written to {path}"
    assert reports.abort_refusal() is None
    controller.abort("aborted by the user (~abort)")
    assert reports.abort_refusal() == "already aborted: aborted by the user (~abort)"

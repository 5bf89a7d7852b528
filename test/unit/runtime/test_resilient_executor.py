"""Environment characterization as the executor runs it (``runtime.resilience.resilient_executor``), no ROS:
the resynthesis job off the stepping thread, the swap, abort and the user's liveness; the executor's
resilience options (``runtime.executor.setup``) and the Controller's ``abort``/``restart_from``."""
from __future__ import annotations

import threading

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from queued_jobs import Jobs

from ltl_stack.runtime.executor.controller import Controller
from ltl_stack.runtime.executor.setup import (
    ExecutorError,
    build_strategy,
    characterization_on,
    check_characterized_spec,
    make_controller,
    merge_options,
    threshold_of,
)
from ltl_stack.runtime.resilience.characterize import (
    ExecutionAborted,
    Mode,
    NegotiationAbort,
    Observation,
    Threshold,
)
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience, Busy, adopt, is_winning
from ltl_stack.spec import SpecError, load_spec, parse_structured
from ltl_stack.synthesis import synthesize

PROBE = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\n\n[ENV_INIT]\ndoor\n\n[ENV_TRANS]\ndoor'\n\n" \
        "[SYS_TRANS]\nperson' -> stop'\n"
# once at, always at, but `at` must end infinitely often: every position with at is losing
STUCK = "[INPUT]\ndoor\n\n[OUTPUT]\nat\n\n[SYS_INIT]\n!at\n\n[SYS_TRANS]\nat -> at'\n\n[SYS_LIVENESS]\n!at\n"
DOOR = "[INPUT]\ndoor\n\n[OUTPUT]\nat\n\n[ENV_INIT]\ndoor\n\n[SYS_INIT]\n!at\n\n[ENV_TRANS]\ndoor'\n\n" \
       "[SYS_TRANS]\nat' -> door'\n\n[SYS_LIVENESS]\nat\n"


def resilient(text: str, tmp_path=None, **kwargs) -> tuple[BackgroundResilience, Controller, Jobs, list]:
    spec = parse_structured(text, "probe.structuredslugs")
    jobs = Jobs()
    installed: list = []
    rs = BackgroundResilience(spec, lock=None, runner=jobs, **kwargs)
    controller = Controller(rs)
    rs.lock = controller.lock
    rs.on_installed = lambda state: installed.append(controller.restart_from(state))
    return rs, controller, jobs, installed


# --- pure functions ---------------------------------------------------------------------------------
def test_is_winning_tells_positions_in_w_from_the_others():
    strategy = synthesize(parse_structured(STUCK, "stuck")).strategy
    assert is_winning(strategy, {"door": True, "at": False}) and is_winning(strategy, {"door": False, "at": False})
    assert not is_winning(strategy, {"door": True, "at": True})


def test_adopt_continues_from_the_current_position_when_winning_or_recovering():
    strategy = synthesize(parse_structured(STUCK, "stuck")).strategy
    seen = Observation(3, 0.0, {"door": True}, {"at": False}, {"door": True})
    here = adopt(strategy, ({"door": False}, {"at": False}), seen, recovery=False)
    assert (here.inputs, here.outputs) == ({"door": False}, {"at": False})
    outside = adopt(strategy, ({"door": False}, {"at": True}), seen, recovery=True)
    assert (outside.inputs, outside.outputs) == ({"door": False}, {"at": True})
    # without recovery a losing position is not taken: the observed initial position instead
    back = adopt(strategy, ({"door": False}, {"at": True}), seen, recovery=False)
    assert (back.inputs, back.outputs) == ({"door": True}, {"at": False})


# --- the job -----------------------------------------------------------------------------------------
def test_violation_starts_one_job_and_recovery_keeps_stop_true_until_the_swap(tmp_path):
    out = tmp_path / "learned.structuredslugs"
    rs, controller, jobs, installed = resilient(PROBE, path=out)
    controller.report_many({"person": False, "door": True})
    assert rs.mode is Mode.NORMAL
    update = controller.report_many({"person": True, "door": False})  # breaks door'
    assert len(jobs.queue) == 1 and rs.mode is Mode.CHARACTERIZING
    assert update.outputs == {"stop": True} and update.violation is None and rs.violated_now
    assert rs.counters.recovery_steps >= 1 and rs.counters.resyntheses == 0 and not out.exists()
    controller.report_many({"person": False, "door": False})  # still violating: recorded, no second job
    controller.report_many({"person": True, "door": False})
    assert len(jobs.queue) == 1 and controller.current_outputs() == {"stop": True}
    assert len(rs.characterizer.ec2) >= 2
    jobs.run_all()
    assert rs.mode is Mode.NORMAL and rs.job is None and rs.counters.resyntheses == 1
    assert rs.counters.ec1 + rs.counters.ec2 == 1
    assert installed and installed[-1].outputs == {"stop": True}
    assert "observed" in out.read_text() and load_spec(out).env_safety
    # the new strategy admits the closed door: further steps are normal
    update = controller.report_many({"person": False, "door": False})
    assert rs.violated_now == [] and rs.mode is Mode.NORMAL


def test_without_recovery_the_controller_holds_while_the_job_runs(tmp_path):
    rs, controller, jobs, installed = resilient(PROBE, recovery=False)
    controller.report_many({"person": True, "door": True})
    assert controller.current_outputs() == {"stop": True}
    update = controller.report_many({"person": True, "door": False})
    assert update.violation is not None and len(jobs.queue) == 1 and rs.mode is Mode.CHARACTERIZING
    assert controller.current_outputs() == {"stop": True}  # held
    jobs.run_all()
    assert rs.mode is Mode.NORMAL and controller.violation is None and controller.current_outputs() == {"stop": True}


def test_abort_while_the_job_runs_drops_its_result():
    rs, controller, jobs, installed = resilient(PROBE)
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    assert jobs.queue
    rs.abort("test")
    controller.abort("test")
    jobs.run_all()
    assert rs.mode is Mode.ABORTED and installed == [] and rs.counters.resyntheses == 0
    assert controller.current_outputs() == {"stop": False}
    assert not controller.report_many({"person": False, "door": True}).stepped
    with pytest.raises(ExecutionAborted):
        rs.add_env_liveness("door")


def test_unrealizable_then_user_liveness_then_normal(tmp_path):
    out = tmp_path / "door.structuredslugs"
    rs, controller, jobs, installed = resilient(DOOR, path=out)
    changed: list = []
    rs.on_changed = lambda: changed.append(rs.mode)
    controller.report_many({"door": True})
    for _ in range(4):  # the door stays closed: EC2 once, then both variants unrealizable
        controller.report_many({"door": False})
        controller.tick()
        jobs.run_all()
        if rs.mode is Mode.WAITING_FOR_USER:
            break
    assert rs.mode is Mode.WAITING_FOR_USER and rs.explanation is not None and Mode.WAITING_FOR_USER in changed
    assert controller.current_outputs() == {"at": False}
    before = out.read_text() if out.exists() else None
    with pytest.raises(SpecError, match="nosuch"):
        rs.add_env_liveness("door | nosuch")
    assert rs.mode is Mode.WAITING_FOR_USER and (out.read_text() if out.exists() else None) == before
    attempt = rs.add_env_liveness("door")
    assert attempt.realizable and rs.mode is Mode.NORMAL and rs.counters.user == 1
    assert "added by the user" in out.read_text() and installed
    controller.report_many({"door": True})
    controller.tick()
    assert controller.state.outputs["at"] or controller.tick().outputs["at"]


def test_user_liveness_is_refused_while_a_job_runs():
    rs, controller, jobs, _ = resilient(PROBE)
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    with pytest.raises(Busy):
        rs.add_env_liveness("door")
    jobs.run_all()
    assert rs.mode is Mode.NORMAL


def test_poll_starts_the_job_once_the_seconds_threshold_passed_without_a_step():
    now = [100.0]
    threshold = Threshold(seconds=2.0, clock=lambda: now[0])
    rs, controller, jobs, _ = resilient(PROBE, threshold=threshold)
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    assert rs.mode is Mode.RECOVERING and not jobs.queue
    assert not rs.poll()
    now[0] += 2.5
    assert rs.poll() and len(jobs.queue) == 1 and rs.mode is Mode.CHARACTERIZING
    assert not rs.poll()  # one job at a time
    jobs.run_all()
    assert rs.counters.resyntheses == 1


def test_a_file_that_cannot_be_written_is_reported_and_the_robot_keeps_running(tmp_path):
    folder = tmp_path / "gone"
    folder.mkdir()
    rs, controller, jobs, installed = resilient(PROBE, path=folder / "learned.structuredslugs")
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    folder.rmdir()  # the folder went away while the node ran
    jobs.run_all()
    assert rs.write_error and "cannot write" in rs.write_error and rs.mode is Mode.NORMAL and installed


def test_threaded_job_installs_under_the_lock():
    spec = parse_structured(PROBE, "probe.structuredslugs")
    done = threading.Event()
    rs = BackgroundResilience(spec, lock=None)
    controller = Controller(rs)
    rs.lock = controller.lock
    rs.on_installed = lambda state: (controller.restart_from(state), done.set())
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    assert done.wait(60), rs.events
    assert rs.mode is Mode.NORMAL and controller.current_outputs() == {"stop": True}


# --- Controller ------------------------------------------------------------------------------------
def test_controller_abort_and_restart_from():
    strategy = synthesize(parse_structured(DOOR, "door")).strategy
    controller = Controller(strategy)
    controller.report_many({"door": True})
    state = strategy.start_state({"door": True}, {"at": True})
    update = controller.restart_from(state)
    assert update.stepped and controller.violation is None
    update = controller.abort("because")
    assert update.outputs == {"at": False} and controller.aborted == "because"
    assert not controller.tick().stepped and not controller.restart_from(state).stepped


# --- executor options ---------------------------------------------------------------------------
def test_characterization_is_off_by_default_and_on_with_a_file(tmp_path):
    assert not characterization_on(merge_options({}))
    assert characterization_on(merge_options({"characterized_spec": str(tmp_path / "x.structuredslugs")}))
    assert characterization_on(merge_options({"characterize": True}))
    assert not characterization_on(merge_options({"characterize": False,
                                                  "characterized_spec": str(tmp_path / "x.structuredslugs")}))


def test_threshold_of_uses_only_the_limits_that_are_set():
    at_once = threshold_of(merge_options({}))
    assert (at_once.transitions, at_once.seconds) == (None, None)
    both = threshold_of(merge_options({"characterize_after_transitions": 150, "characterize_after_seconds": 2.5}))
    assert (both.transitions, both.seconds) == (150, 2.5)


@pytest.mark.parametrize("values, needle", [
    ({"characterize_after_transitions": -1}, "--characterize-after-transitions must be a number >= 0"),
    ({"characterize_after_seconds": float("nan")}, "--characterize-after-seconds must be"),
    ({"characterize": True, "strategy": "s.json"}, "cannot be used with --strategy"),
])
def test_bad_resilience_options_name_the_flag(values, needle):
    with pytest.raises(ExecutorError, match=needle.replace("(", r"\(")):
        merge_options(values)


def test_bad_resilience_parameters_name_the_parameter(tmp_path):
    with pytest.raises(ExecutorError, match="parameter ~characterize_after_seconds must be a number >= 0"):
        merge_options({}, lambda name: (name == "characterize_after_seconds", -2))
    with pytest.raises(ExecutorError, match="is a folder"):
        merge_options({}, lambda name: (name == "characterized_spec", str(tmp_path)))
    with pytest.raises(ExecutorError, match="folder does not exist"):
        merge_options({}, lambda name: (name == "characterized_spec", str(tmp_path / "no" / "x.spec")))


def test_the_characterized_spec_must_not_be_an_input(tmp_path):
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE)
    options = merge_options({"characterized_spec": str(spec)})
    with pytest.raises(ExecutorError, match="--characterized-spec"):
        check_characterized_spec(options, [str(spec), None, None])
    check_characterized_spec(merge_options({"characterized_spec": str(tmp_path / "new.spec")}), [str(spec)])


def test_build_strategy_with_characterization_gives_the_controller_its_lock(tmp_path):
    spec = parse_structured(PROBE, "probe.structuredslugs")
    options = merge_options({"characterized_spec": str(tmp_path / "learned.structuredslugs")})
    strategy = build_strategy(spec, options, log=lambda _text: None)
    assert isinstance(strategy, BackgroundResilience) and strategy.recovery
    controller = make_controller(strategy, options, {})
    assert strategy.lock is controller.lock


def test_build_strategy_unrealizable_is_exit_10():
    spec = parse_structured("[INPUT]\na\n\n[OUTPUT]\nb\n\n[SYS_TRANS]\nb' <-> a'\nb' <-> !a'\n", "bad")
    with pytest.raises(ExecutorError, match="unrealizable") as err:
        build_strategy(spec, merge_options({"characterize": True}), log=lambda _text: None)
    assert int(err.value.code) == 10


# --- the characterized spec of a Structured English spec ---------------------------------
ENGLISH = ("# the issue's probe in Structured English\nSensors: person, door\nActions: stop\n\n"
           "Environment starts with door\nAssume always you are sensing door\n"
           "If you are sensing person then do stop\n")


def english_run(tmp_path, text: str, readings: list[dict], out_name: str = "learned.spec"):
    source = tmp_path / "probe.spec"
    source.write_text(text)
    spec = load_spec(source)
    jobs = Jobs()
    out = tmp_path / out_name
    rs = BackgroundResilience(spec, lock=None, runner=jobs, path=out)
    controller = Controller(rs)
    rs.lock = controller.lock
    rs.on_installed = controller.restart_from
    for values in readings:
        controller.report_many(values)
        jobs.run_all()
    return rs, out


def test_english_spec_is_characterized_in_english(tmp_path):
    rs, out = english_run(tmp_path, ENGLISH, [{"person": False, "door": True}, {"person": True, "door": False}])
    assert rs.counters.resyntheses == 1, rs.events
    text = out.read_text()
    assert "If you are sensing person then do stop" in text  # the user's sentences stay
    assert "# replaced by environment characterization: Assume always you are sensing door" in text
    assert "# disjunct 1: EC1 (Eq. 4.3) observed" in text and "Assume always you are sensing door or" in text
    assert "Robot starts with" in text and "[ENV_TRANS]" not in text
    learned = load_spec(out)  # reads as English (no section headers) ...
    assert learned.source == str(out) and len(learned.env_safety) == 1
    running = rs.characterizer.history[-1].spec  # ... and says what runs
    assert synthesize(learned).realizable and running.inputs == learned.inputs
    attempt = rs.add_env_liveness("door")
    assert attempt.realizable
    text = out.read_text()
    assert "(Alg. 3 line 6): door" in text and "Assume infinitely often door" in text, text
    assert len(load_spec(out).env_liveness) == 1


def test_english_that_cannot_say_it_falls_back_to_the_structured_format(tmp_path):
    # a sentence giving an init clause *and* a guarantee cannot be replaced alone
    mixed = ENGLISH.replace("Environment starts with door\n", "Environment starts with door\n") + \
        "Regions: a, b\n"
    rs, out = english_run(tmp_path, mixed, [{"person": False, "door": True, "a_rc": True, "b_rc": False},
                                            {"person": True, "door": False, "a_rc": True, "b_rc": True}])
    text = out.read_text()
    assert rs.counters.resyntheses == 1, rs.events
    assert text.startswith("# Written in the structured format, not in English:"), text[:300]
    assert "[ENV_TRANS]" in text and load_spec(out).env_safety
    assert any("structured format, not English" in e.message for e in rs.events)


def test_a_structured_spec_with_a_spec_file_is_written_structured(tmp_path):
    out = tmp_path / "learned.spec"
    rs, controller, jobs, _ = resilient(PROBE, path=out)
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    jobs.run_all()
    assert "[ENV_TRANS]" in out.read_text() and load_spec(out).env_safety


# --- the negotiation hook ---------------------------------------------------------------------------
def closed_door_until(rs, controller, jobs, done) -> None:
    controller.report_many({"door": True})
    for _ in range(6):
        controller.report_many({"door": False})
        controller.tick()
        jobs.run_all()
        if done():
            return


@pytest.mark.parametrize("agree", [True, False, None])
def test_negotiation_hook_runs_in_the_job_and_its_spec_is_installed_or_the_run_aborts(agree):
    """agree: an agreed spec runs; False: no agreement (4.8.3 / line 20), abort; None: negotiation does
    not apply (no peer involved, absent or silent, already negotiated): S.1, the user."""
    agreed = parse_structured(DOOR.replace("[ENV_TRANS]\ndoor'", "[ENV_LIVENESS]\ndoor"), "agreed")
    calls: list = []

    def negotiate(strategy, observation):
        calls.append((strategy.job, observation.incoming))
        if agree is False:
            raise NegotiationAbort("4.8.3")
        return agreed if agree else None

    rs, controller, jobs, installed = resilient(DOOR, negotiate=negotiate)
    closed_door_until(rs, controller, jobs, lambda: calls)
    assert calls and calls[0][0] is not None  # busy while negotiating: no second job
    assert calls[0][1] == {"door": False}
    if agree:
        assert rs.mode is Mode.NORMAL and installed and rs.counters.resyntheses >= 1
        assert rs.counters.negotiated == 1 and rs.counters.ec1 + rs.counters.ec2 + rs.counters.negotiated \
            == rs.counters.resyntheses
        assert rs.counters.unrealizable >= 1 and [e for e in rs.events if "negotiation" in e.message]
    elif agree is False:
        assert rs.mode is Mode.ABORTED and not installed and rs.counters.negotiated == 0
    else:
        assert rs.mode is Mode.WAITING_FOR_USER and rs.explanation is not None and not installed
        assert rs.counters.unrealizable == 1 and [e for e in rs.events if "S.1" in e.message]


def test_after_a_negotiation_it_initiated_a_robot_characterizes_again_only_once_an_input_changes():
    """The handover: the agreed spec assumes the peer's door' from the next step on, and the steps that
    still read the door the peer published before it adopted are recovered, not characterized (that
    would drop the promise just agreed). Once an input changes, a violation is characterized again."""
    agreed = parse_structured(DOOR, "agreed")  # the peer promised door' (always next door)
    calls: list = []

    def negotiate(strategy, observation):
        calls.append(observation.incoming)
        return agreed if len(calls) == 1 else None

    rs, controller, jobs, installed = resilient(DOOR, negotiate=negotiate)
    closed_door_until(rs, controller, jobs, lambda: installed)
    assert installed and rs.counters.negotiated == 1 and len(calls) == 1
    for _ in range(3):  # the door is still closed: the peer's output from before its adoption
        controller.tick()
        jobs.run_all()
    assert rs.job is None and not jobs.queue and len(calls) == 1 and rs.mode is Mode.RECOVERING
    assert [e for e in rs.events if "handover" in e.message]
    controller.report_many({"door": True})  # the promised output arrives
    assert rs.mode is Mode.NORMAL
    controller.report_many({"door": False})  # and is broken later: characterized as usual (then S.1)
    jobs.run_all()
    assert len(calls) == 2 and rs.mode is Mode.WAITING_FOR_USER


def test_a_peer_whose_promised_output_never_comes_is_characterized_once_the_handover_ends():
    """The handover is bounded (HANDOVER_SECONDS): with the door still closed and no step at all, the
    node's poll starts the characterization the handover held back."""
    now = [0.0]
    agreed = parse_structured(DOOR, "agreed")
    calls: list = []

    def negotiate(strategy, observation):
        calls.append(observation.incoming)
        return agreed if len(calls) == 1 else None

    rs, controller, jobs, installed = resilient(DOOR, negotiate=negotiate, threshold=Threshold(clock=lambda: now[0]))
    closed_door_until(rs, controller, jobs, lambda: installed)
    controller.tick()
    jobs.run_all()
    assert not rs.poll() and len(calls) == 1 and rs.mode is Mode.RECOVERING  # within the handover
    now[0] += BackgroundResilience.HANDOVER_SECONDS
    assert rs.poll()  # the promised door never came
    said = [e.message for e in rs.events]
    assert any(m.startswith("the handover after the negotiated adoption is over") for m in said), said
    assert said[-1].startswith("characterizing (") and "after 0" not in said[-1], said
    jobs.run_all()
    assert len(calls) == 2 and rs.mode is Mode.WAITING_FOR_USER


def test_adopt_drops_a_running_job():
    rs, controller, jobs, installed = resilient(PROBE)
    controller.report_many({"person": False, "door": True})
    controller.report_many({"person": True, "door": False})
    assert jobs.queue
    spec = parse_structured(PROBE.replace("[ENV_TRANS]\ndoor'\n", "").replace("[ENV_INIT]\ndoor\n", ""), "agreed")
    strategy = synthesize(spec).strategy
    with controller.lock:
        controller.state = rs.adopt(spec, "agreed", strategy, {"person": True, "door": False}, {"stop": True})
    jobs.run_all()
    assert installed == [] and rs.mode is Mode.NORMAL and rs.counters.resyntheses == 1
    assert rs.strategy is strategy


# --- property: the guarantees hold at every step, whenever the jobs run ------------------------------
@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@example([(False, False, False), (True, False, False), (True, True, True)], True)  # person while a job runs
@example([(True, False, False), (False, False, True), (True, False, False)], False)
@given(st.lists(st.tuples(st.booleans(), st.booleans(), st.booleans()), min_size=1, max_size=12),
       st.booleans())
def test_outputs_keep_the_guarantees_while_resynthesizing(moves, recovery):
    """Random readings of the probe (person, door: door' is the assumption) with the resynthesis jobs
    run at random moments: every published valuation keeps person -> stop (recovery on; off: when the
    controller is not holding after a violation), the counters add up, nothing raises."""
    rs, controller, jobs, _ = resilient(PROBE, recovery=recovery)
    controller.report_many({"person": False, "door": True})
    for person, door, run_jobs in moves:
        update = controller.report_many({"person": person, "door": door})
        if run_jobs:
            jobs.run_all()
        if controller.state is not None and (recovery or controller.violation is None):
            outputs = controller.current_outputs()
            assert not controller.readings["person"] or outputs["stop"] or update.violation is not None, \
                (controller.readings, outputs, rs.events)
        assert rs.mode in set(Mode)
        c = rs.counters
        assert c.resyntheses == c.ec1 + c.ec2 + c.user
    jobs.run_all()
    assert rs.job is None and rs.mode is not Mode.CHARACTERIZING


def test_is_english_and_english_text_refuses_a_structured_running_spec(tmp_path):
    from ltl_stack.runtime.resilience.characterize import Characterizer
    from ltl_stack.runtime.resilience.characterized_english import english_text, is_english

    assert is_english("a/b.spec") and is_english("x.ENGLISH") and not is_english("x.structuredslugs")
    ch = Characterizer(parse_structured(PROBE, str(tmp_path / "probe.structuredslugs")), path=tmp_path / "o.spec")
    seen = Observation(1, 0.0, {"person": False, "door": True}, {"stop": False}, {"person": True, "door": False})
    ch.record(seen)
    text, why = english_text(ch, "EC1", seen, ch.parse(ch.text("EC1", seen)), [])
    assert text is None and "not a Structured English file" in why

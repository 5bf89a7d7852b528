"""What the executor publishes in each mode and phase (``runtime.executor.node_reports``), no ROS."""
from __future__ import annotations

import os
import re

import pytest

from ltl_stack.runtime.executor.node_reports import liveness_refusal, strategy_source
from ltl_stack.runtime.executor.setup import ExecutorError, check_characterized_spec, merge_options
from ltl_stack.runtime.resilience.characterize import Mode
from ltl_stack.runtime.resilience.resilient_executor import BackgroundResilience, NotReady
from ltl_stack.spec import SpecError, parse_structured

PROBE = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\n\n[ENV_INIT]\ndoor\n\n[ENV_TRANS]\ndoor'\n\n" \
        "[SYS_TRANS]\nperson' -> stop'\n"


def test_strategy_source_names_the_original_then_the_written_spec_and_counts_generations(tmp_path):
    assert strategy_source("probe.structuredslugs", None) == (os.path.abspath("probe.structuredslugs"), 0)
    written = tmp_path / "ch.structuredslugs"
    rs = BackgroundResilience(parse_structured(PROBE, "probe.structuredslugs"), lock=None, path=written)
    assert strategy_source("probe.structuredslugs", rs) == (os.path.abspath("probe.structuredslugs"), 0)
    rs.counters.resyntheses = 2
    assert strategy_source("probe.structuredslugs", rs) == (str(written), 2)
    rs.write_error = "cannot write"
    assert strategy_source("probe.structuredslugs", rs) == ("", 2)


# --- the user's liveness and the characterized spec never trace back ------------------
@pytest.mark.parametrize("text, needle", [
    ("[ENV_TRANS]", "is a section header, not a formula"),
    ("[INPUT]", "is a section header, not a formula"),
    ("door\u2028person", "U+2028"), ("door\x0bperson", "U+000B"), ("door\x1cperson", "U+001C"),
    ("door\x85person", "U+0085"), ("door\u2029!door", "U+2029"),
])
def test_liveness_that_is_a_header_or_two_lines_is_one_error_and_nothing_changes(text, needle):
    rs = BackgroundResilience(parse_structured(PROBE, "probe.structuredslugs"), lock=None)
    rs.initial_state({"person": False, "door": True})
    with pytest.raises(SpecError, match=re.escape(needle)):
        rs.add_env_liveness(text)
    assert rs.characterizer.user_liveness == [] and rs.counters.resyntheses == 0


def test_liveness_before_the_controller_started_is_not_ready():
    rs = BackgroundResilience(parse_structured(PROBE, "probe.structuredslugs"), lock=None)
    with pytest.raises(NotReady, match="not ready"):
        rs.add_env_liveness("door")
    assert rs.job is None and rs.mode is Mode.NORMAL


def test_liveness_refusal_says_why_by_mode():
    assert "characterization is off" in liveness_refusal(False, True, "waiting_for_user")
    assert "not ready" in liveness_refusal(True, False, "normal")
    assert "already aborted" in liveness_refusal(True, True, "aborted")
    assert "not waiting for the user (mode normal)" in liveness_refusal(True, True, "normal")
    assert liveness_refusal(True, True, "waiting_for_user") is None


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_characterized_spec_naming_a_fifo_or_a_device_is_refused(tmp_path, kind):
    if kind == "fifo":
        target = tmp_path / "pipe"
        os.mkfifo(target)
    else:
        target = "/dev/null"
    options = merge_options({"characterized_spec": str(target)})
    with pytest.raises(ExecutorError, match="not a regular file"):
        check_characterized_spec(options, [str(tmp_path / "spec.structuredslugs")])


def test_history_and_events_stay_bounded_over_many_resyntheses():
    """Each attempt holds a strategy and its BDD manager; only the last is kept."""
    import itertools

    from ltl_stack.runtime.executor.controller import Controller
    from ltl_stack.runtime.resilience.characterize import EVENTS_KEPT, HISTORY_KEPT

    text = "[INPUT]\na\nb\nc\nd\n\n[OUTPUT]\nx\n\n[ENV_INIT]\n!a\n\n[ENV_TRANS]\n!a'\n\n[SYS_TRANS]\nb' -> x'\n"
    rs = BackgroundResilience(parse_structured(text, "flood.structuredslugs"), lock=None, runner=lambda job: job())
    controller = Controller(rs)
    rs.lock = controller.lock
    rs.on_installed = controller.restart_from
    controller.report_many(dict.fromkeys("abcd", False))
    for bits in itertools.product([False, True], repeat=3):  # 8 new violating valuations (a = 1)
        controller.report_many({"a": True, **dict(zip("bcd", bits))})
        controller.report_many(dict.fromkeys("abcd", False))
    assert rs.counters.resyntheses >= 5, rs.counters
    assert len(rs.characterizer.history) <= HISTORY_KEPT == 1 and len(rs.events) <= EVENTS_KEPT


def test_violation_report_names_the_broken_and_the_unkeepable_clauses():
    """Item 9: the violation report is ROS-free; without a safe valuation it says so and names the
    guarantees (file:line)."""
    from ltl_stack.runtime.executor.node_reports import violation_report
    from ltl_stack.synthesis.errors import AssumptionViolation

    spec = parse_structured("[INPUT]\np\n\n[OUTPUT]\nx\n\n[ENV_TRANS]\n!p'\n\n[SYS_TRANS]\np' -> x'\np' -> !x'\n", "s")
    broken = AssumptionViolation(list(spec.env_safety), {"p": True})
    report = violation_report(broken, None, list(spec.sys_safety), {"p": True}, 3, False, "hold")
    assert "s:8: !p'" in report.text and "no move keeps the system safety" in report.text
    assert "s:11: p' -> x'; s:12: p' -> !x'" in report.text and "publishing the hold valuation" in report.text
    assert ("unsafe_clause", "s:12: p' -> !x'") in report.values and report.event["unsafe"] == [
        "s:11: p' -> x'", "s:12: p' -> !x'"]
    kept = violation_report(broken, None, [], {"p": True}, 3, False, "all-false", {"x": True})
    assert "the fewest outputs true that keep the system safety" in kept.text and "unsafe" not in kept.event
    assert "publishing outputs x" in kept.text  # what was published, not the last state's outputs

"""Resilient execution in the real executor node (thesis ch. 4; docs/resilience.md): recovery with
environment characterization, the threshold, the characterized spec file, the user's env liveness
through ``~add_env_liveness`` (and the ``add_env_liveness`` tool), ``~abort``, UNSAFE steps.

A probe process plays the input proposition nodes and reports outputs, ``~state`` (mode, counters,
violated clauses) and ``/diagnostics`` as JSON lines (test_executor_node's Probe).
"""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest
from helpers import run_script, wait_for
from test_executor_node import Probe

pytestmark = pytest.mark.ros

# The probe: the environment promises the door stays open; the robot must stop for a person.
PROBE_SPEC = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\n\n[ENV_INIT]\ndoor\n\n[ENV_TRANS]\ndoor'\n\n" \
             "[SYS_TRANS]\nperson' -> stop'\n"
DOOR_CLAUSE_LINE = 12
PERSON, DOOR, STOP = "/probe/inputs/person", "/probe/inputs/door", "/probe/outputs/stop"
STATE = "/controller_executor/state"

# The robot must visit `at` infinitely often and may only be there with the door open; the
# environment promises the door stays open. Closing it for good: EC2 once (closing for one step),
# then EC1 and EC2 both unrealizable (the door may stay closed forever) -> the user says the door
# opens infinitely often.
DOOR_SPEC = "[INPUT]\ndoor\n\n[OUTPUT]\nat\n\n[ENV_INIT]\ndoor\n\n[SYS_INIT]\n!at\n\n[ENV_TRANS]\ndoor'\n\n" \
            "[SYS_TRANS]\nat' -> door'\n\n[SYS_LIVENESS]\nat\n"
DOOR_IN, AT = "/door/inputs/door", "/door/outputs/at"

# Both inputs together break the assumption and leave no move keeping both guarantees.
UNSAFE_SPEC = "[INPUT]\na\nb\n\n[OUTPUT]\nx\n\n[ENV_INIT]\n!a & !b\n\n[ENV_TRANS]\n!(a' & b')\n\n" \
              "[SYS_TRANS]\na' -> x'\nb' -> !x'\n"
A_IN, B_IN, X_OUT = "/unsafe/inputs/a", "/unsafe/inputs/b", "/unsafe/outputs/x"

class ResilienceProbe(Probe):
    """``Probe`` with the resilience services and views of ``~state``."""

    def liveness(self, formula: str) -> dict:
        count = len(self.of("called"))
        self.send(op="liveness", service="/controller_executor/add_env_liveness", formula=formula)
        return wait_for(lambda: self.of("called")[count:], 120, "the ~add_env_liveness answer")[0]

    def states(self) -> list[dict]:
        return [s for s in self.of("state") if s["state"] >= 0 or s["mode"] == "aborted"]

    def wait_state(self, predicate, what: str, timeout: float = 60) -> dict:
        return wait_for(lambda: [s for s in self.states() if predicate(s)], timeout,
                        f"{what} (states: {self.states()[-3:]})")[-1]


@pytest.fixture
def rprobes(ros_master, tmp_path):
    started: list[ResilienceProbe] = []

    def start(listen: list[str]) -> ResilienceProbe:
        probe = ResilienceProbe(ros_master, tmp_path, listen, name=f"rprobe{len(started)}")
        started.append(probe)
        return probe

    yield start
    for probe in started:
        probe.stop()


def executor(ros_master, spec: Path, *extra: str, inputs: tuple[str, ...]):
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), "--json",
                           "--violation-grace", "0", *extra], name="executor")
    for topic in inputs:
        ros_master.wait_for_subscriber(topic, timeout=60)
    return node


def events(node, kind: str) -> list[dict]:
    return [json.loads(x) for x in node.output().splitlines() if x.startswith(f'{{"event": "{kind}"')]


def probe_start(ros_master, rprobes, tmp_path, *extra: str):
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE_SPEC)
    node = executor(ros_master, spec, *extra, inputs=(PERSON, DOOR))
    probe = rprobes([f"bool:{STOP}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish(PERSON, False)
    probe.publish(DOOR, True)
    probe.wait_state(lambda s: s["inputs"] == {"person": False, "door": True}, "the initial state")
    return spec, node, probe


def test_probe_under_recovery_keeps_stop_true_below_the_threshold(ros_master, rprobes, tmp_path):
    out = tmp_path / "learned.structuredslugs"
    spec, node, probe = probe_start(ros_master, rprobes, tmp_path, "--characterized-spec", str(out),
                                    "--characterize-after-transitions", "100000")
    probe.publish(DOOR, False)  # breaks door' (line 12)
    probe.publish(PERSON, True)
    probe.wait_value(STOP, True, timeout=60)
    state = probe.wait_state(lambda s: s["inputs"] == {"person": True, "door": False} and s["mode"] == "recovering",
                             "a recovering state with person=1 door=0")
    assert state["outputs"] == {"stop": True}, state
    assert any(f"{spec}:{DOOR_CLAUSE_LINE}: door'" in c for c in state["violated"]), state
    assert state["violations"] >= 1 and state["recovery_steps"] >= 1 and state["resyntheses"] == 0, state
    diag = wait_for(lambda: [d for d in probe.of("diag") if d["name"].endswith(": mode") and d["level"] == 1
                             and "recovering" in d["message"]], 60, "a WARN mode diagnostic")[-1]
    assert f"{spec}:{DOOR_CLAUSE_LINE}: door'" in diag["message"], diag
    assert not out.exists(), "no resynthesis below the threshold, so nothing to write"
    assert node.running() and "Traceback" not in node.output(), node.output()


def test_violation_past_the_threshold_resynthesizes_and_the_file_loads(ros_master, rprobes, tmp_path):
    out = tmp_path / "learned.structuredslugs"
    spec, node, probe = probe_start(ros_master, rprobes, tmp_path, "--characterized-spec", str(out),
                                    "--characterize-after-seconds", "1")
    trace = ros_master.run(["rosrun", "ltl_stack", "controller_trace", STATE], name="trace")
    probe.publish(PERSON, True)
    probe.wait_value(STOP, True)
    trace.wait_output("doing: stop", timeout=60)
    probe.publish(DOOR, False)  # the violation lasts: no step happens, the 1 s threshold passes
    state = probe.wait_state(lambda s: s["resyntheses"] >= 1 and s["mode"] == "normal",
                             "a resynthesis and mode normal", timeout=90)
    assert state["ec1"] + state["ec2"] == state["resyntheses"], state
    assert state["inputs"] == {"person": True, "door": False} and state["outputs"] == {"stop": True}, state
    # stop stayed true from person=1 on: recovery moves meanwhile, the new strategy afterwards
    assert [e["value"] for e in probe.of("bool", topic=STOP)][-1] is True, probe.of("bool")
    modes = [s["mode"] for s in probe.states()]
    assert "characterizing" in modes or "recovering" in modes, modes
    assert all(s["outputs"] == {"stop": True} for s in probe.states() if s["inputs"].get("person")), probe.states()
    text = wait_for(lambda: out.exists() and out.read_text(), 90, "the characterized spec")
    assert "EC1 (Eq. 4.3) observed" in text or "EC2 (Eq. 4.4) observed" in text, text
    assert f"{spec}:{DOOR_CLAUSE_LINE}: door'" in text, text
    done = run_script(["rosrun", "ltl_stack", "synthesize", str(out)], capture_output=True, text=True,
                          timeout=300, env=dict(ros_master.env))
    assert done.returncode == 0, done.stderr
    check = run_script(["rosrun", "ltl_stack", "controller_executor", str(out), "--check"], capture_output=True,
                           text=True, timeout=300, env=dict(ros_master.env))
    assert check.returncode == 0, check.stderr
    # and the node keeps working: the person leaves, stop may drop
    probe.publish(PERSON, False)
    probe.wait_state(lambda s: s["inputs"] == {"person": False, "door": False}, "a step with person=0")
    assert node.running() and "Traceback" not in node.output(), node.output()
    assert [e for e in events(node, "resilience") if "resynthesized" in e["message"]], node.output()
    log = trace.wait_output("*** resynthesized (EC", timeout=60)
    assert "-> recovering" in log or "-> characterizing" in log, log


def door_start(ros_master, rprobes, tmp_path, *extra: str):
    spec = tmp_path / "door.structuredslugs"
    spec.write_text(DOOR_SPEC)
    node = executor(ros_master, spec, "--characterize", *extra, inputs=(DOOR_IN,))
    probe = rprobes([f"bool:{AT}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish(DOOR_IN, True)
    probe.wait_state(lambda s: s["inputs"] == {"door": True}, "the initial state")
    return spec, node, probe


def test_user_liveness_round_trip(ros_master, rprobes, tmp_path):
    out = tmp_path / "door_learned.structuredslugs"
    spec, node, probe = door_start(ros_master, rprobes, tmp_path, "--characterized-spec", str(out))
    probe.publish(DOOR_IN, False)  # closed for good
    waiting = probe.wait_state(lambda s: s["mode"] == "waiting_for_user", "waiting for the user", timeout=120)
    assert waiting["unrealizable"] >= 1, waiting
    diag = wait_for(lambda: [d for d in probe.of("diag") if d["name"].endswith(": mode")
                             and "waiting for the user" in d["message"]], 60, "the waiting diagnostic")[-1]
    assert diag["level"] == 1 and any(k == "explanation" for k, _ in diag["values"]), diag
    assert probe.last(AT) is False, probe.of("bool")  # at' -> door' kept while waiting

    before = len(probe.states())
    bad = probe.liveness("door | nosuch")
    assert bad["success"] is False and bad["code"] == 2 and "nosuch" in bad["message"], bad
    assert "env liveness:1:" in bad["message"], bad
    assert bad["mode"] == "waiting_for_user", bad
    assert all(s["mode"] == "waiting_for_user" for s in probe.states()[before:]), probe.states()[before:]

    good = run_script(["rosrun", "ltl_stack", "add_env_liveness", "--json", "door"], capture_output=True,
                          text=True, timeout=300, env=dict(ros_master.env))
    assert good.returncode == 0, (good.stdout, good.stderr)
    answer = json.loads(good.stdout)
    assert answer["success"] is True and answer["mode"] in ("normal", "recovering", "holding"), answer
    state = probe.wait_state(lambda s: s["user"] == 1, "the user resynthesis on ~state")
    assert state["resyntheses"] >= 1, state
    text = out.read_text()
    assert "added by the user" in text and "door" in text, text
    # the door opens: the robot may visit `at` again
    probe.publish(DOOR_IN, True)
    probe.wait_value(AT, True, timeout=60)
    assert node.running() and "Traceback" not in node.output(), node.output()


def test_abort_drives_every_output_false_and_reports_error(ros_master, rprobes, tmp_path):
    spec, node, probe = probe_start(ros_master, rprobes, tmp_path, "--characterize")
    probe.publish(PERSON, True)
    probe.wait_value(STOP, True)
    done = run_script(["rosrun", "ltl_stack", "add_env_liveness", "--abort"], capture_output=True, text=True,
                          timeout=300, env=dict(ros_master.env))
    assert done.returncode == 0, (done.stdout, done.stderr)
    probe.wait_value(STOP, False, timeout=60)
    probe.wait_state(lambda s: s["mode"] == "aborted", "mode aborted on ~state")
    wait_for(lambda: [d for d in probe.of("diag") if d["name"].endswith(": mode") and d["level"] == 2
                      and "aborted" in d["message"]], 60, "an ERROR diagnostic")
    # inputs keep coming: nothing steps, nothing crashes, outputs stay false
    count = len(probe.of("bool", topic=STOP))
    probe.publish(PERSON, False)
    probe.publish(PERSON, True)
    wait_for(lambda: len([d for d in probe.of("diag") if d["level"] == 2]) >= 3, 60, "more ERROR diagnostics")
    assert all(e["value"] is False for e in probe.of("bool", topic=STOP)[count:]), probe.of("bool")
    again = probe.liveness("door")
    assert again["success"] is False and again["mode"] == "aborted", again
    assert node.running() and "Traceback" not in node.output(), node.output()


@pytest.mark.parametrize("characterize", [False, True])
def test_unsafe_step_is_reported_loudly(ros_master, rprobes, tmp_path, characterize):
    spec = tmp_path / "unsafe.structuredslugs"
    spec.write_text(UNSAFE_SPEC)
    node = executor(ros_master, spec, *(["--characterize"] if characterize else []), inputs=(A_IN, B_IN))
    probe = rprobes([f"bool:{X_OUT}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish(A_IN, False)
    probe.publish(B_IN, False)
    probe.wait_state(lambda s: s["inputs"] == {"a": False, "b": False}, "the initial state")
    probe.publish(A_IN, True)
    probe.wait_value(X_OUT, True)
    probe.publish(B_IN, True)  # breaks line 12 and no move keeps lines 15 and 16 together
    diag = wait_for(lambda: [d for d in probe.of("diag") if d["level"] == 2 and "cannot all be kept" in d["message"]],
                    60, "an ERROR naming the guarantees that cannot be kept")[-1]
    assert f"{spec}:15" in diag["message"] and f"{spec}:16" in diag["message"], diag
    state = probe.wait_state(lambda s: s["unsafe_steps"] >= 1, "unsafe_steps on ~state")
    assert state["mode"] in ("holding", "characterizing", "waiting_for_user"), state
    assert "cannot all be kept" in node.output(), node.output()
    assert node.running() and "Traceback" not in node.output(), node.output()


@pytest.mark.parametrize("args, needle", [
    (["_characterize_after_seconds:=-1"], "~characterize_after_seconds must be a number >= 0"),
    (["--characterize-after-transitions", "-2"], "--characterize-after-transitions must be a number >= 0"),
    (["_characterize:=maybe"], "~characterize must be a bool"),
    (["--characterize", "--strategy", "saved.json"], "cannot be used with --strategy"),
])
def test_bad_resilience_parameters_are_one_fatal_line(ros_master, tmp_path, args, needle):
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE_SPEC)
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), *args], name="executor")
    code = wait_for(lambda: node.popen.poll(), 60, "the executor to exit")
    log = node.output()
    assert code == 2 and needle in log and log.count("[FATAL]") == 1 and "Traceback" not in log, log


def test_characterized_spec_naming_the_spec_is_refused(ros_master, tmp_path):
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE_SPEC)
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), "--characterized-spec",
                           str(spec)], name="executor")
    code = wait_for(lambda: node.popen.poll(), 60, "the executor to exit")
    assert code == 2 and "--characterized-spec" in node.output() and spec.read_text() == PROBE_SPEC, node.output()


def tool(args: list[str], env: dict) -> subprocess.CompletedProcess:
    return run_script(["rosrun", "ltl_stack", "add_env_liveness", *args], capture_output=True, text=True,
                          timeout=300, env=env)


@pytest.mark.parametrize("args, code, needle", [
    (["door", "--abort"], 2, "either a formula or --abort"),
    ([], 2, "either a formula or --abort"),
    (["  "], 2, "the formula is empty"),
    (["--node", "a//b", "door"], 2, "not a legal ROS name"),
    (["--master-uri", "localhost:1", "door"], 2, "is not a ROS master URI"),
    (["--timeout", "2", "door"], 3, "no service /controller_executor/add_env_liveness"),
])
def test_add_env_liveness_tool_bad_input(ros_master, args, code, needle):
    done = tool(args, dict(ros_master.env))
    errors = [line for line in done.stderr.splitlines() if "error" in line]
    assert done.returncode == code and needle in done.stderr and len(errors) == 1, (done.returncode, done.stderr)
    assert "Traceback" not in done.stderr


def test_add_env_liveness_tool_without_a_master_is_exit_3(tmp_path):
    from helpers import closed_port

    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{closed_port()}/"}
    done = tool(["--timeout", "1", "door"], env)
    assert done.returncode == 3 and "no ROS master" in done.stderr, done.stderr
    helped = tool(["--help"], env)
    assert helped.returncode == 0 and "usage: add_env_liveness" in helped.stdout, helped.stdout


def test_add_env_liveness_with_characterization_off_says_so(ros_master, rprobes, tmp_path):
    spec, node, probe = probe_start(ros_master, rprobes, tmp_path)
    answer = probe.liveness("door")
    assert answer["success"] is False and answer["code"] == 1 and "--characterize" in answer["message"], answer
    done = tool(["door"], dict(ros_master.env))
    assert done.returncode == 1 and "characterization is off" in done.stderr, done.stderr
    # abort works without characterization too
    probe.publish(PERSON, True)
    probe.wait_value(STOP, True)
    assert tool(["--abort", "--json"], dict(ros_master.env)).returncode == 0
    probe.wait_value(STOP, False, timeout=60)
    probe.wait_state(lambda s: s["mode"] == "aborted", "mode aborted")


ENGLISH_PROBE = ("Sensors: person, door\nActions: stop\n\nEnvironment starts with door\n"
                 "Assume always you are sensing door\nIf you are sensing person then do stop\n")


def test_transitions_threshold_at_a_fixed_rate_and_an_english_characterized_spec(ros_master, rprobes, tmp_path):
    spec = tmp_path / "probe.spec"
    spec.write_text(ENGLISH_PROBE)
    out = tmp_path / "learned.spec"
    node = executor(ros_master, spec, "--rate", "20", "--characterized-spec", str(out),
                    "--characterize-after-transitions", "10", inputs=(PERSON, DOOR))
    probe = rprobes([f"bool:{STOP}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish(PERSON, True)
    probe.publish(DOOR, True)
    probe.wait_value(STOP, True)
    probe.publish(DOOR, False)  # at 20 Hz the violation outlasts 10 transitions in about half a second
    state = probe.wait_state(lambda s: s["resyntheses"] >= 1, "the resynthesis", timeout=90)
    recovering = [s for s in probe.states() if s["mode"] == "recovering"]
    assert recovering and all(s["outputs"] == {"stop": True} for s in recovering), probe.states()
    assert max(s["violations"] for s in recovering) >= 1, recovering
    assert state["outputs"] == {"stop": True}, state
    text = wait_for(lambda: out.exists() and out.read_text(), 90, "the characterized spec")
    assert "# replaced by environment characterization: Assume always you are sensing door" in text, text
    assert "If you are sensing person then do stop" in text and "[ENV_TRANS]" not in text, text
    done = run_script(["rosrun", "ltl_stack", "synthesize", str(out)], capture_output=True, text=True,
                          timeout=300, env=dict(ros_master.env))
    assert done.returncode == 0, done.stderr
    assert node.running() and "Traceback" not in node.output(), node.output()


def test_a_one_step_violation_shows_as_recovering_on_state(ros_master, rprobes, tmp_path):
    """door -> door': closing the door breaks it once; staying closed is admissible again, so the
    settling step after the recovery move is normal. ~state still says the update recovered."""
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE_SPEC.replace("[ENV_TRANS]\ndoor'", "[ENV_TRANS]\ndoor -> door'"))
    executor(ros_master, spec, "--characterize", "--characterize-after-transitions", "100000",
             inputs=(PERSON, DOOR))
    probe = rprobes([f"bool:{STOP}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish(PERSON, False)
    probe.publish(DOOR, True)
    probe.wait_state(lambda s: s["inputs"] == {"person": False, "door": True}, "the initial state")
    probe.publish(DOOR, False)
    state = probe.wait_state(lambda s: s["mode"] == "recovering", "a recovering ~state")
    assert any(f"{spec}:{DOOR_CLAUSE_LINE}: door -> door'" in c for c in state["violated"]), state
    assert state["recovery_steps"] >= 1 and state["resyntheses"] == 0, state


def test_add_env_liveness_never_traces_back_and_says_not_ready_not_waiting_already_aborted(ros_master, rprobes,
                                                                                            tmp_path):
    """Before the controller started: exit 1 "not ready" (was a KeyError in the
    service, exit 3); a section header or two formulas joined by U+2028: exit 2, one line; while not
    waiting for the user: exit 1 as the README says; ``--abort`` twice: the second is exit 1."""
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE_SPEC)
    node = executor(ros_master, spec, "--characterize", inputs=(PERSON, DOOR))
    env = dict(ros_master.env)
    early = tool(["door"], env)  # no input has reported: the controller has not started
    assert early.returncode == 1 and "not ready" in early.stderr, (early.returncode, early.stderr)
    for formula, needle in (("[ENV_TRANS]", "section header"), ("door\u2028person", "U+2028")):
        done = tool([formula], env)
        errors = [line for line in done.stderr.splitlines() if "error" in line]
        assert done.returncode == 2 and needle in done.stderr and len(errors) == 1, (done.returncode, done.stderr)
    probe = rprobes([f"bool:{STOP}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish(PERSON, False)
    probe.publish(DOOR, True)
    probe.wait_state(lambda s: s["inputs"] == {"person": False, "door": True}, "the initial state")
    normal = tool(["door"], env)
    assert normal.returncode == 1 and "not waiting for the user (mode normal)" in normal.stderr, normal.stderr
    assert tool(["--abort"], env).returncode == 0
    again = tool(["--abort"], env)
    assert again.returncode == 1 and "already aborted" in again.stderr, (again.returncode, again.stderr)
    assert node.running() and "Traceback" not in node.output(), node.output()


def test_a_failed_write_of_the_characterized_spec_is_an_error_on_diagnostics(ros_master, rprobes, tmp_path):
    folder = tmp_path / "gone"
    folder.mkdir()
    out = folder / "learned.structuredslugs"
    spec, node, probe = probe_start(ros_master, rprobes, tmp_path, "--characterized-spec", str(out))
    folder.rmdir()  # the write after the resynthesis fails; the new strategy runs anyway
    probe.publish(DOOR, False)
    probe.wait_state(lambda s: s["resyntheses"] >= 1, "a resynthesis")
    diag = wait_for(lambda: [d for d in probe.of("diag") if d["name"].endswith(": spec file") and d["level"] == 2],
                    60, "an ERROR about the spec file")[-1]
    assert f"cannot write {out}" in diag["message"], diag
    state = probe.wait_state(lambda s: s["resyntheses"] >= 1 and s["spec_file"] == "", "spec_file empty")
    assert state["generation"] >= 1, state
    assert node.running() and "Traceback" not in node.output(), node.output()


def test_with_negotiation_configured_a_violation_no_peer_is_involved_in_asks_the_user(ros_master, rprobes, tmp_path):
    """Alg. 3 by cause (§4.4): the mapping declares a peer, but the broken clause
    (door') names none of its eAP inputs: S.1 — the explanation and ~add_env_liveness — not an abort."""
    spec = tmp_path / "door.structuredslugs"
    spec.write_text(DOOR_SPEC.replace("[INPUT]\ndoor\n", "[INPUT]\ndoor\nbeacon\n"))
    mapping = tmp_path / "door.yaml"
    mapping.write_text("negotiation:\n  robot: R\n  peers:\n    Z:\n      eap: {beacon: signal}\n")
    out = tmp_path / "door_learned.structuredslugs"
    node = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping), "--json",
                           "--violation-grace", "0", "--characterized-spec", str(out), "--negotiation-timeout", "2"],
                          name="executor")
    ros_master.wait_for_subscriber(DOOR_IN, timeout=60)
    probe = rprobes([f"bool:{AT}", f"state:{STATE}", "diag:/diagnostics"])
    probe.publish("/door/inputs/beacon", False)
    probe.publish(DOOR_IN, True)
    probe.wait_state(lambda s: s["inputs"] == {"door": True, "beacon": False}, "the initial state")
    probe.publish(DOOR_IN, False)  # closed for good: EC1 and EC2 unrealizable
    waiting = probe.wait_state(lambda s: s["mode"] in ("waiting_for_user", "aborted"), "S.1 or an abort",
                               timeout=120)
    assert waiting["mode"] == "waiting_for_user", (waiting, node.output()[-3000:])
    good = probe.liveness("door")
    assert good["success"] is True, good
    assert node.running() and "Traceback" not in node.output(), node.output()

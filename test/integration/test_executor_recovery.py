"""Recovery after an environment-assumption violation (thesis §4.6) in the real executor node.

The probe spec of the issue: the environment promises the door stays open, the robot must stop when
it sees a person. person=1 door=0 breaks the promise; with recovery (the default) the executor still
steps and keeps ``person' -> stop'``; with ``--no-recovery`` it holds the outputs that keep the system
safety (Lemma 1(a)): stop=true as well.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import direct_script, wait_for
from test_executor_node import probes  # noqa: F401 - fixture

pytestmark = pytest.mark.ros

PROBE_SPEC = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\n\n[ENV_INIT]\ndoor\n\n[ENV_TRANS]\ndoor'\n\n" \
             "[SYS_TRANS]\nperson' -> stop'\n"
PERSON, DOOR, STOP = "/probe/inputs/person", "/probe/inputs/door", "/probe/outputs/stop"
STATE = "/controller_executor/state"


@pytest.mark.parametrize("recovery", [True, False])
def test_violation_is_recovered_and_stop_stays_true(ros_master, probes, tmp_path, recovery):  # noqa: F811
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(PROBE_SPEC)
    extra = ["--json", "--violation-grace", "0"] + ([] if recovery else ["--no-recovery"])
    executor = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), *extra], name="executor")
    ros_master.wait_for_subscriber(PERSON)
    ros_master.wait_for_subscriber(DOOR)
    probe = probes([f"bool:{STOP}", "diag:/diagnostics", f"state:{STATE}"])
    probe.publish(PERSON, False)
    probe.publish(DOOR, True)
    probe.wait_value(STOP, False)
    probe.publish(DOOR, False)  # breaks door' (line 12)
    executor.wait_output('"event": "violation"', timeout=60)  # seen before person changes (one topic each)
    probe.publish(PERSON, True)
    log = wait_for(lambda: executor.output().count('"event": "violation"') >= 2 and executor.output(), 60,
                   "the second violation (person=1 door=0)")
    if recovery:
        probe.wait_value(STOP, True, timeout=60)
        diag = wait_for(lambda: [d for d in probe.of("diag") if d["level"] == 1 and "recovering" in d["message"]],
                        60, "a WARN diagnostic about the recovery")[0]
        assert f"{spec}:12: door'" in diag["message"], diag
        wait_for(lambda: "recovering (" in executor.output(), 60, "the recovery log line")
    else:
        diag = wait_for(lambda: [d for d in probe.of("diag") if d["level"] == 2], 60, "an ERROR diagnostic")[0]
        assert f"{spec}:12: door'" in diag["message"], diag
        probe.wait_value(STOP, True, timeout=60)  # Lemma 1(a): the held outputs keep person' -> stop'
        assert probe.last(STOP) is True, probe.of("bool")
    events = [json.loads(x) for x in executor.output().splitlines() if x.startswith('{"event": "violation"')]
    assert events and all(e["recovered"] is recovery for e in events), events
    if recovery:
        assert {e["kind"] for e in events} <= {"recover_to_w", "recover_towards_w", "safe_only"}, events
    assert "Traceback" not in log, log
    assert executor.running(), executor.output()
    if recovery:
        # door=0 is in no state of the automaton, so the recovered state has a symbolic id; with the
        # readings admissible again the executor is back on the ids of `synthesize --strategy-json`
        exported = tmp_path / "probe.json"
        done = subprocess.run(direct_script(["rosrun", "ltl_stack", "synthesize", str(spec), "--strategy-json",
                                             str(exported)], ros_master.env),
                              env=ros_master.env, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        states = {s["id"]: (s["goal"], s["inputs"], s["outputs"]) for s in json.loads(exported.read_text())["states"]}
        recovered = wait_for(lambda: [e for e in probe.of("state") if e["inputs"] == {"person": True, "door": False}],
                             60, "the recovered state on ~state")[-1]
        assert all(v[1]["door"] for v in states.values()), states
        probe.publish(DOOR, True)
        probe.publish(PERSON, False)
        back = wait_for(lambda: [e for e in probe.of("state") if e["inputs"] == {"person": False, "door": True}
                                 and e["t"] > recovered["t"]], 60, "a state with the door open again")[-1]
        assert states.get(back["state"]) == (back["goal"], back["inputs"], back["outputs"]), (back, states)


# The probe: two outputs, a goal; door=0 breaks the assumption, then a person appears.
TWO_SPEC = "[INPUT]\nperson\ndoor\n\n[OUTPUT]\nstop\npass\n\n[ENV_INIT]\ndoor\n\n[SYS_INIT]\n!pass\n\n" \
           "[ENV_TRANS]\ndoor'\n\n[SYS_TRANS]\nperson' -> stop'\npass' -> door'\n\n[SYS_LIVENESS]\npass\n"
MODES = {"recovery": [], "hold": ["--no-recovery"], "all-false": ["--no-recovery", "--on-violation", "all-false"],
         "characterization only": ["--no-recovery", "--characterized-spec", "{tmp}/ch.structuredslugs"],
         "characterization with recovery": ["--characterized-spec", "{tmp}/ch.structuredslugs"]}


def break_door_then_see_a_person(ros_master, make_probe):
    """With the executor subscribed: door=1 and no person (a first state), then door=0 (breaks door'),
    then a person: the probe of ~state, once the state with door=0 was published."""
    ros_master.wait_for_subscriber(PERSON)
    ros_master.wait_for_subscriber(DOOR)
    probe = make_probe([f"state:{STATE}"])
    probe.publish(PERSON, False)
    probe.publish(DOOR, True)
    wait_for(lambda: [e for e in probe.of("state") if e["inputs"] == {"person": False, "door": True}], 60,
             "the first state")
    probe.publish(DOOR, False)  # breaks door'
    wait_for(lambda: [e for e in probe.of("state") if e["inputs"] == {"person": False, "door": False}], 60,
             "a state with door=0")
    probe.publish(PERSON, True)
    return probe


def assert_every_state_with_a_person_keeps_the_guarantees(probe) -> None:
    """person' -> stop' and pass' -> door' in every published state with a person."""
    states = [e for e in probe.of("state") if e["inputs"]["person"]]
    assert states, probe.of("state")
    bad = [e for e in states if not e["outputs"]["stop"] or (e["outputs"]["pass"] and not e["inputs"]["door"])]
    assert not bad, bad


@pytest.mark.parametrize("mode", list(MODES))
def test_person_door_probe_keeps_stop_true_in_every_mode(ros_master, probes, tmp_path, mode):  # noqa: F811
    """Lemma 1(a) in every mode: with door=0 (assumption broken) and person=1 every valuation
    the node publishes afterwards keeps person' -> stop' and pass' -> door' — while holding, while
    characterizing and while waiting for the user."""
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(TWO_SPEC)
    extra = [a.format(tmp=tmp_path) for a in MODES[mode]]
    executor = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), "--json",
                               "--violation-grace", "0", *extra], name="executor")
    probe = break_door_then_see_a_person(ros_master, probes)
    seen = wait_for(lambda: [e for e in probe.of("state") if e["inputs"] == {"person": True, "door": False}], 60,
                    "a state with person=1 door=0")
    if "characterization" in mode:  # and through the resynthesis (or the wait for the user)
        wait_for(lambda: probe.of("state")[-1]["mode"] != "characterizing" and probe.of("state")[-1]["t"] >= seen[0]["t"],
                 120, "characterization done")
    assert_every_state_with_a_person_keeps_the_guarantees(probe)
    assert "Traceback" not in executor.output(), executor.output()


# Negotiation configured: door is the peer P's openDoor (an eAP input, §4.8), so when
# characterization finds no realizable spec the node negotiates with P (a real party node, Alg. 4),
# adopts what they agree (4.8.1: P guarantees openDoor, R may assume door infinitely often) and, door
# still closed, characterizes again on the adopted spec.
PARTY = Path(__file__).with_name("negotiation_party.py")
R_MAP = ("negotiation:\n  robot: R\n  peers:\n    P:\n      service: /t/P/controller_executor/negotiate\n"
         "      eap: {door: openDoor}\n")
P_SPEC = "[INPUT]\nbell\n\n[OUTPUT]\nopenDoor\n\n[SYS_LIVENESS]\nopenDoor\n"
P_MAP = "negotiation:\n  robot: P\n  peers:\n    R:\n      service: /controller_executor/negotiate\n" \
        "      shares: {openDoor: door}\n"


@pytest.mark.parametrize("recovery", [[], ["--no-recovery"]], ids=["recovery", "no-recovery"])
def test_person_door_probe_keeps_stop_true_with_negotiation_configured(ros_master, probes, tmp_path,  # noqa: F811
                                                                       recovery):
    """Lemma 1(a) with negotiation configured: door=0 (assumption broken) and person=1 — while
    characterizing, negotiating with P, right after adopting and characterizing again — every
    valuation the node publishes keeps person' -> stop' and pass' -> door'."""
    spec = tmp_path / "probe.structuredslugs"
    spec.write_text(TWO_SPEC)
    mapping = tmp_path / "r.yaml"
    mapping.write_text(R_MAP)
    (tmp_path / "p.structuredslugs").write_text(P_SPEC)
    (tmp_path / "p.yaml").write_text(P_MAP)
    peer = ros_master.run([sys.executable, str(PARTY), "responder", str(tmp_path / "p.structuredslugs"),
                           str(tmp_path / "p.yaml"), "--timeout", "20", "__ns:=/t/P"], name="peer-P")
    peer.wait_output('"ready"', timeout=60)
    executor = ros_master.run(["rosrun", "ltl_stack", "controller_executor", str(spec), str(mapping), "--json",
                               "--violation-grace", "0", "--characterized-spec", str(tmp_path / "ch.structuredslugs"),
                               "--negotiation-timeout", "20", *recovery], name="executor")
    # door is P's openDoor; still closed with a person: no characterized spec is realizable, R negotiates with P
    probe = break_door_then_see_a_person(ros_master, probes)
    wait_for(lambda: '"report"' in peer.output(), 120, "P's negotiation report")
    after = wait_for(lambda: [e for e in probe.of("state")[-1:] if e["resyntheses"] >= 2 and e["inputs"]["person"]
                              and e["mode"] != "characterizing"], 120, "the node settled on the adopted spec")[0]
    assert after["mode"] != "aborted", (after, executor.output()[-3000:])
    assert '"case": "BOTH_ADOPT"' in peer.output(), peer.output()
    assert_every_state_with_a_person_keeps_the_guarantees(probe)
    assert "Traceback" not in executor.output() + peer.output(), executor.output() + peer.output()

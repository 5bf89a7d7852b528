"""Stories (scripted environments that react to the robot, ``runtime.resilience.story``): the format, its
errors, and the player both the in-process comparison and the ROS node use."""
from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.errors import Exit
from ltl_stack.runtime.resilience.story import StoryError, StoryPlayer, load_story, parse_story
from ltl_stack.spec import load_spec, parse_structured

CONFIG = Path(__file__).resolve().parents[3] / "config"

STORY = """\
regions: [a, b]
inputs: {door: true, tap: false}
pulse: [tap]
user: "door"
beats:
  - name: first
    set: {door: false}
  - name: in b
    when: {at: b}
    after: 2
    set: {tap: true}
  - name: heading a with o
    when: {heading: a, outputs: {o: true}}
"""


def test_beats_fire_in_order_once_their_condition_holds():
    player = StoryPlayer(parse_story(STORY, "s.yaml"))
    assert player.tick("a", {"a": True}).name == "first" and player.values["door"] is False
    assert player.tick("b", {"b": True}) is None, "'after: 2' counts from the previous beat"
    beat = player.tick("b", {"a": True})  # exactly 2 transitions after 'first'
    assert beat.name == "in b" and player.values["tap"] is True and player.pending_pulses() == ["tap"]
    player.read()
    assert player.values["tap"] is False, "a pulse lasts until the controller has read it"
    assert player.tick("b", {"a": True, "o": False}) is None
    assert player.tick("b", {"b": True, "o": True}) is None, "heading b, not a"
    assert not player.complete
    assert player.tick("b", {"a": True, "o": True}).name == "heading a with o"
    assert player.complete and player.tick("a", {}) is None
    assert [f.tick for f in player.fired] == [1, 3, 6]


def test_a_wait_counts_only_transitions_the_controller_made_with_the_last_beats_values():
    """On ROS a beat's values travel to the executor: the transitions it makes before they arrive do
    not count towards the next beat's ``after`` (so a busy machine cannot shorten the story's waits)."""
    player = StoryPlayer(parse_story(STORY, "s.yaml"))
    assert player.tick("a", {}).name == "first"  # door: false is on its way
    for _ in range(5):
        player.not_seen_yet({"door": True, "tap": False})  # the executor still steps with door true
        assert player.tick("b", {}) is None
    player.not_seen_yet({"door": False, "tap": False})
    assert player.tick("b", {}) is None  # the first transition with the new value
    player.not_seen_yet({"door": False, "tap": False})
    assert player.tick("b", {}).name == "in b"  # 2 transitions with door false
    player.not_seen_yet({"door": False, "tap": False})  # the pulse not read yet: not counted
    assert player.pending_pulses() == ["tap"] and player.since == player.ticks + 1
    player.read()  # the controller stepped with the pulse
    since = player.since
    player.not_seen_yet({"door": False, "tap": False})  # a read pulse is false again: that is no news
    assert player.since == since
    assert player.tick("a", {"a": True, "o": True}).name == "heading a with o"


@pytest.mark.parametrize("text, message", [
    ("beats: 3", "expected a mapping with a 'beats:' list"),
    ("beats: []\nplot: 1", "unknown key(s) plot"),
    ("inputs: {a: 1}\nbeats: []", "'inputs' must map names to true/false"),
    ("inputs: {a: true}\npulse: [b]\nbeats: []", "'pulse' must list names given in 'inputs'"),
    ("regions: [r]\nbeats:\n  - name: x\n    when: {at: q}", "s.yaml:3: beat #0: 'at: q' is not one of the regions"),
    ("beats:\n  - name: x\n  - name: y\n    after: -1", "s.yaml:3: beat #1: 'after' must be a number"),
    ("inputs: {a: true}\nbeats:\n  - name: x\n    set: {b: true}", "s.yaml:3: beat #0: 'set' names b"),
    ("beats:\n  - name: x\n    when: {mode: y}", "'when' takes at, heading, outputs"),
    ("beats:\n  - {set: {}}", "expected a mapping with a 'name'"),
    ("threshold: yes\nbeats: []", "'threshold' must be a number"),
    ("beats: [\n", "s.yaml:"),
    # the user's env liveness must parse and name a proposition of the story
    ("inputs: {door: true}\nuser: 'TRUE'\nbeats: []", "s.yaml:2: 'user': 'TRUE' names no proposition"),
    ("inputs: {door: true}\nuser: '1'\nbeats: []", "s.yaml:2: 'user': '1' names no proposition"),
    ("inputs: {door: true}\nuser: 'door |'\nbeats: []", "s.yaml:2: 'user': 'door |' does not parse (column"),
    ("inputs: {door: true}\nuser: 'window'\nbeats: []", "s.yaml:2: 'user': 'window' does not parse"),
    ("regions: [r]\nuser: 'r_c & !r'\nbeats: []", None),
])
def test_bad_stories_are_refused_with_file_and_line(text, message):
    if message is None:  # a good one: regions give r_c (input) and r (output)
        assert parse_story(text, "s.yaml").user
        return
    with pytest.raises(StoryError) as info:
        parse_story(text, "s.yaml")
    assert message in str(info.value) and info.value.code == Exit.BAD_INPUT


def test_missing_and_binary_files_are_story_errors(tmp_path):
    with pytest.raises(StoryError, match="missing.yaml"):
        load_story(tmp_path / "missing.yaml")
    (tmp_path / "bin.yaml").write_bytes(b"beats: []\0")
    with pytest.raises(StoryError, match="bin.yaml"):
        load_story(tmp_path / "bin.yaml")


def test_story_is_checked_against_the_spec():
    spec = parse_structured("[INPUT]\na_c\ndoor\ntap\n[OUTPUT]\na\no\n", "t.structuredslugs")
    parse_story("regions: [a]\ninputs: {door: true, tap: false}\nbeats: []", "s.yaml").check(spec)
    for text, message in [
        ("regions: [a, b]\ninputs: {door: true, tap: false}\nbeats: []", "region 'b' needs output b and input b_c"),
        ("regions: [a]\ninputs: {door: true}\nbeats: []", "inputs tap are neither regions"),
        ("regions: [a]\ninputs: {door: true, tap: false, x: true}\nbeats: []", "'inputs:' names x"),
        ("regions: [a]\ninputs: {door: true, tap: false}\nstop: halt\nbeats: []", "'stop: halt'"),
        ("regions: [a]\ninputs: {door: true, tap: false}\nbeats:\n  - name: n\n    when: {outputs: {q: true}}",
         "'q' is not an output"),
        ("regions: [a]\ninputs: {door: true, tap: false}\nstop: halt\nuser: 'halt'\nbeats: []", "'stop: halt'"),
    ]:
        with pytest.raises(StoryError, match="s.yaml") as info:
            parse_story(text, "s.yaml").check(spec)
        assert message in str(info.value)


@pytest.mark.parametrize("example, spec", [("alice", "alice"), ("patrol_recycling", "patrol_recycling"),
                                           ("block_cutting", "block_cutting")])
def test_shipped_stories_fit_their_specs(example, spec):
    story = load_story(CONFIG / example / "story.yaml")
    story.check(load_spec(CONFIG / example / f"{spec}.structuredslugs"))
    assert story.beats


@given(st.lists(st.tuples(st.integers(0, 3), st.sampled_from([None, "a", "b"])), min_size=1, max_size=6),
       st.lists(st.sampled_from(["a", "b"]), min_size=1, max_size=40))
def test_player_fires_each_beat_once_in_order_after_its_wait(beats, path):
    """Whatever the robot does: beats fire in file order, at most one per transition, never before
    their ``after`` transitions since the previous one, and only where their ``at`` holds."""
    lines = ["regions: [a, b]", "inputs: {}", "beats:"]
    for k, (after, at) in enumerate(beats):
        lines += [f"  - name: b{k}", f"    after: {after}"] + ([f"    when: {{at: {at}}}"] if at else [])
    player = StoryPlayer(parse_story("\n".join(lines), "p.yaml"))
    previous = 0
    for where in path:
        fired = player.tick(where, {where: True})
        if fired is not None:
            k = int(fired.name[1:])
            assert k == len(player.fired) - 1
            assert player.ticks - previous >= beats[k][0]
            assert beats[k][1] in (None, where)
            previous = player.ticks
    assert len(player.fired) <= len(path)

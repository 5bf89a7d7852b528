"""Graph snapshots: built from the master's lists, saved and loaded as YAML or JSON, bad files."""
from __future__ import annotations

import pytest
from analysis_data import DATA, scenarios
from hypothesis import given, settings
from hypothesis import strategies as st

from ltl_stack.analysis.snapshot import Snapshot, SnapshotError

SYSTEM_STATE = (
    [["/cmd_vel", ["/stop", "/move_base"]], ["/rosout", ["/stop"]]],
    [["/cmd_vel", ["/base"]]],
    [["/stop/get_loggers", ["/stop"]]],
)


def test_from_system_state_collects_nodes_types_and_sides():
    snap = Snapshot.from_system_state(*SYSTEM_STATE, [["/cmd_vel", "geometry_msgs/Twist"]], master="http://m:1/")
    assert snap.nodes == ["/base", "/move_base", "/stop"], snap.nodes
    assert snap.topics["/cmd_vel"].type == "geometry_msgs/Twist"
    assert snap.topics["/cmd_vel"].publishers == ["/move_base", "/stop"]
    assert snap.topics["/cmd_vel"].subscribers == ["/base"]
    assert snap.topics["/rosout"].type == "", "a topic without a known type keeps ''"
    assert snap.services == {"/stop/get_loggers": ["/stop"]}


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_save_then_load_gives_the_same_snapshot(tmp_path, suffix):
    snap = scenarios.scenario_snapshot(DATA / "clean_and_patrol.yaml")
    path = tmp_path / f"graph{suffix}"
    snap.save(path)
    assert Snapshot.load(path) == snap
    assert list(tmp_path.iterdir()) == [path], "no temporary file is left behind"


names = st.lists(st.sampled_from(["/a", "/b", "/ns/c", "/d_1"]), max_size=4, unique=True)


@settings(max_examples=40, deadline=None)
@given(st.dictionaries(st.sampled_from(["/t1", "/t2", "/x/goal", "/weird name"]),
                       st.tuples(st.sampled_from(["", "std_msgs/Bool"]), names, names), max_size=4))
def test_dict_round_trip(topics):
    pubs = [(t, p) for t, (_, p, _) in topics.items()]
    subs = [(t, s) for t, (_, _, s) in topics.items()]
    types = [(t, ty) for t, (ty, _, _) in topics.items()]
    snap = Snapshot.from_system_state(pubs, subs, [], types)
    assert Snapshot.from_dict(snap.to_dict()) == snap


@pytest.mark.parametrize("text, message", [
    ("nodes: [/a\n", "invalid YAML"),
    ("topics:\n  5: {publishers: [/x]}\n", ":2: key '5' is not a string"),
    ("nodes: [/a]\nyes: 1\n", ":2: key 'yes' is not a string"),
    ("~: 1\n", ":1: key '~' is not a string"),
    ("nodes: " + "[" * 100000 + "\n", ":1: nested more than 100 levels deep"),
    ("taken: " + "1" * 5000 + "\n", ":1: integer of 5000 digits"),
    ("- just\n- a list\n", "expected a mapping"),
    ("format: other/2\n", "unknown format 'other/2'"),
    ("topics: [/a]\n", "'topics' must be a mapping"),
    ("topics:\n  /a: {publishers: /x}\n", "topic /a: publishers: expected a list of names"),
    ("services: {/s: [1]}\n", "service /s: expected a list of names"),
])
def test_bad_files_raise_one_clear_error(tmp_path, text, message):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(SnapshotError) as err:
        Snapshot.load(path)
    assert str(err.value).startswith(str(path)), err.value
    assert message in str(err.value), err.value


def test_bad_json_names_line(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"nodes": [\n "/a",\n]}')
    # Python 3.13's json names the trailing comma itself (line 2), older ones the next value (line 3)
    with pytest.raises(SnapshotError, match=r"bad\.json:(3: invalid JSON: .* \(column 1\)|2: invalid JSON: "
                                            r"Illegal trailing comma .* \(column 6\))"):
        Snapshot.load(path)


@pytest.mark.parametrize("text, message", [
    ('{"nodes": ' + "[" * 100000 + "\n", ":1: nested more than 100 levels deep"),
    ('{"taken": ' + "1" * 5000 + "}", "invalid JSON value"),
    ('{"topics": {"/t": {"publishers": ["/a\\"[["]}}, "nodes": [\n' + "[" * 200, ":2: nested more than"),
])
def test_bad_json_snapshots(tmp_path, text, message):
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(SnapshotError) as err:
        Snapshot.load(path)
    assert str(err.value).startswith(str(path)) and message in str(err.value), err.value
    assert err.value.code == 2


def test_missing_binary_and_non_utf8_files(tmp_path):
    with pytest.raises(SnapshotError, match="nope.yaml: no such file"):
        Snapshot.load(tmp_path / "nope.yaml")
    binary = tmp_path / "s.json"
    binary.write_bytes(b'{"nodes":\n ["/a\x00"]}')
    with pytest.raises(SnapshotError, match=r"s\.json:2: not a text snapshot: it holds a NUL byte"):
        Snapshot.load(binary)
    latin = tmp_path / "s.yaml"
    latin.write_bytes(b"nodes: [/caf\xe9]\n")
    with pytest.raises(SnapshotError, match=r"s\.yaml:1: not a text snapshot: not UTF-8"):
        Snapshot.load(latin)

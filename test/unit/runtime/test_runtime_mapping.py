"""The mapping YAML loader and its validation against a spec's propositions."""
from __future__ import annotations

import textwrap

import pytest
import yaml
from helpers import require_shared, shared_dir
from hypothesis import given
from hypothesis import strategies as st

from ltl_stack.runtime.config.mapping import (
    MappingError,
    check_mapping,
    default_topic,
    format_mapping,
    load_mapping,
    parse_mapping,
    resolve_name,
    resolve_topics,
)

SIMPLE = textwrap.dedent("""\
    inputs:
      person:
        node: 'person'
        node_publish_topic: '/simple/inputs/person'
        pkg: 'controller_executor'
        filename: 'get_tag.py'
        parameters:
          tag_no: 5
    outputs:
      move:
        node: 'move'
        node_subscribe_topic: '/simple/outputs/move'
        pkg: 'controller_executor'
        filename: 'set_velocity.py'
      stop:
        - node: '/simple/outputs/r1/stop'
          node_subscribe_topic: '/simple/outputs/stop'
        - node: '/simple/outputs/r2/stop'
          node_subscribe_topic: '/simple/outputs/stop'
    """)


def issue_texts(mapping, inputs, outputs):
    return [str(i) for i in check_mapping(mapping, inputs, outputs)]


def test_parse_reads_nodes_topics_parameters_and_lines():
    m = parse_mapping(SIMPLE, "m.yaml")
    person = m.inputs["person"][0]
    assert (person.node, person.topic, person.pkg, person.executable) == (
        "person", "/simple/inputs/person", "controller_executor", "get_tag.py"), person
    assert person.parameters == {"tag_no": 5}, person.parameters
    assert [e.node for e in m.outputs["stop"]] == ["/simple/outputs/r1/stop", "/simple/outputs/r2/stop"]
    assert m.line_of("input", "person") == 2, m.lines
    assert m.line_of("output", "stop") == 15, m.lines
    assert [e.line for e in m.outputs["stop"]] == [16, 18]
    assert m.scenario_namespace() == "simple"


def test_clean_mapping_has_no_issues():
    m = parse_mapping(SIMPLE, "m.yaml")
    assert issue_texts(m, ["person"], ["move", "stop"]) == []


def test_unknown_and_unmapped_propositions_are_named_with_lines():
    m = parse_mapping(SIMPLE, "m.yaml")
    got = issue_texts(m, ["person", "radio"], ["move"])
    assert got == [
        "m.yaml: warning: input 'radio' is not mapped to any node; the executor uses its default topic",
        "m.yaml:15: error: output 'stop' is not a proposition of the spec (its outputs: move)",
    ], got


def test_proposition_of_the_other_kind_is_an_error():
    m = parse_mapping(SIMPLE, "m.yaml")
    got = issue_texts(m, ["person", "move"], ["stop"])
    assert "m.yaml:10: error: 'move' is mapped as an output but the spec declares it as an input" in got, got


def test_input_with_two_nodes_is_a_duplicate_publisher_error():
    text = textwrap.dedent("""\
        inputs:
          person:
            - node: 'other'
              node_publish_topic: '/simple/inputs/person'
            - node: 'person'
              node_publish_topic: '/simple/inputs/person'
        """)
    m = parse_mapping(text, "m.yaml")
    errors = [i for i in check_mapping(m, ["person"], []) if i.severity == "error"]
    assert len(errors) == 1, errors
    assert errors[0].proposition == "person" and errors[0].line == 2, errors
    assert "mapped to 2 nodes (other, person)" in errors[0].message, errors[0].message


def test_two_propositions_on_one_topic_is_an_error():
    text = SIMPLE.replace("'/simple/outputs/move'", "'/simple/outputs/stop'")
    got = issue_texts(parse_mapping(text, "m.yaml"), ["person"], ["move", "stop"])
    assert got == ["m.yaml:15: error: output 'move' and output 'stop' share the proposition topic "
                   "/simple/outputs/stop; each proposition needs its own"], got


@pytest.mark.parametrize("text, line, fragment", [
    ("inputs:\n  a: [1, 2\n", 3, "invalid YAML"),
    ("inputs:\n  a:\n    node: x\n    nod_publish_topic: t\n", 4, "unknown key 'nod_publish_topic'"),
    ("inputs:\n  a:\n    node: x\ninputs:\n  b:\n    node: y\n", 4, "'inputs' appears twice (first on line 1)"),
    ("outputs:\n  a:\n    node: x\n  a:\n    nod: y\n", 5, "unknown key 'nod'"),
    ("inputs:\n  a:\n    node: x\n    node_subscribe_topic: t\n", 4, "use node_publish_topic"),
    ("outputs:\n  b: 3\n", 2, "output 'b': expected a node entry or a list"),
    ("outputs:\n  b:\n    - node: x\n    - 7\n", 4, "a node entry must be a mapping"),
    ("outputs:\n  b:\n    node: 'bad name!'\n", 3, "node 'bad name!' is not a valid ROS name"),
    ("outputs:\n  b:\n    node: x\n    parameters: [1]\n", 4, "parameters must be a mapping"),
    ("robots: []\n", 1, "unknown top-level key 'robots'"),
    ("outputs:\n  b:\n    node: x\n    robot: 'r 1'\n", 4, "robot 'r 1' is not a legal ROS base name"),
    ("outputs:\n  b:\n    node: x\n    robot: r__1\n", 4, "robot 'r__1' is not a legal ROS base name"),
    ("- a\n", 1, "must be a YAML mapping"),
    ("inputs:\n  a: {}\n  5: {node: x}\n", 3, "key '5' is not a string"),
    ("outputs:\n  yes:\n    node: x\n", 2, "key 'yes' is not a string"),
    ("~: 1\n", 1, "key '~' is not a string"),
    ("inputs:\n  a:\n    node: x\n    parameters: {n: " + "7" * 5000 + "}\n", 4, "integer of 5000 digits"),
    ("inputs:\n  a: " + "[" * 100000 + "\n", 2, "nested more than"),
])
def test_malformed_files_raise_one_error_with_line(text, line, fragment):
    with pytest.raises(MappingError) as info:
        parse_mapping(text, "bad.yaml")
    assert info.value.line == line, str(info.value)
    assert fragment in str(info.value), str(info.value)
    assert str(info.value).startswith(f"bad.yaml:{line}: "), str(info.value)


def test_missing_file_is_a_mapping_error(tmp_path):
    with pytest.raises(MappingError) as info:
        load_mapping(tmp_path / "nope.yaml")
    assert str(info.value) == f"{tmp_path / 'nope.yaml'}: no such file", str(info.value)
    binary = tmp_path / "m.yaml"
    binary.write_bytes(b"inputs:\n  a:\n    node: x\x00\n")
    with pytest.raises(MappingError) as info:
        load_mapping(binary)
    assert str(info.value) == f"{binary}:3: not a text mapping file: it holds a NUL byte", str(info.value)
    assert info.value.code == 2


def test_topics_default_under_the_namespace_and_relative_names_resolve_in_groups():
    assert default_topic("ns", "input", "a") == "/ns/inputs/a"
    assert resolve_name("x", "ns", "output") == "/ns/outputs/x"
    assert resolve_name("/abs//x", "ns", "output") == "/abs/x"
    m = parse_mapping("inputs:\n  a:\n    node: n\n    node_publish_topic: rel\noutputs:\n  b:\n    node: m\n", "m")
    ins, outs = resolve_topics(m, ["a", "c"], ["b", "d"], "ns")
    assert ins == {"a": "/ns/inputs/rel", "c": "/ns/inputs/c"}, ins
    assert outs == {"b": ["/ns/outputs/b"], "d": ["/ns/outputs/d"]}, outs


def test_explicit_namespace_key_wins():
    m = parse_mapping("namespace: /robot1\n" + SIMPLE, "m")
    assert m.scenario_namespace() == "robot1"


def test_an_output_with_nodes_on_two_topics_publishes_on_both():
    text = SIMPLE.replace("r2/stop'\n      node_subscribe_topic: '/simple/outputs/stop'",
                          "r2/stop'\n      node_subscribe_topic: '/simple/outputs/stop2'")
    _, outs = resolve_topics(parse_mapping(text, "m"), [], ["stop"], "simple")
    assert outs == {"stop": ["/simple/outputs/stop", "/simple/outputs/stop2"]}, outs


NAMES = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_", min_size=1, max_size=8)


@given(st.dictionaries(NAMES, st.lists(NAMES, min_size=1, max_size=3, unique=True), max_size=5),
       st.dictionaries(st.sampled_from(["k", "gain", "flag"]), st.integers() | st.booleans(), max_size=3))
def test_any_written_mapping_reads_back(outputs, parameters):
    data = {"outputs": {prop: [{"node": f"/ns/outputs/{n}/{prop}", "node_subscribe_topic": f"/ns/outputs/{prop}",
                                "parameters": parameters} for n in nodes] for prop, nodes in outputs.items()}}
    m = parse_mapping(yaml.safe_dump(data), "gen.yaml")
    got = {prop: [e.node for e in es] for prop, es in m.outputs.items()}
    assert got == {prop: [f"/ns/outputs/{n}/{prop}" for n in nodes] for prop, nodes in outputs.items()}, got
    assert all(e.parameters == parameters for e in m.entries())
    assert check_mapping(m, [], list(outputs)) == []


def _spec_props(slugsin: str) -> tuple[list[str], list[str]]:
    """Input and output names of a .slugsin file (a tiny reader so this test needs no spec parser)."""
    sections: dict[str, list[str]] = {}
    current = None
    for raw in slugsin.splitlines():
        line = raw.split("#", 1)[0].strip()
        if line.startswith("["):
            current = line
            sections[current] = []
        elif line and current:
            sections[current].append(line)
    return sections.get("[INPUT]", []), sections.get("[OUTPUT]", [])


@pytest.mark.parametrize("scenario", ["simple", "tutorial", "firefighting", "move_group_and_move_base",
                                      "spheros", "spheros_problem"])
def test_the_thesis_mappings_load_as_they_are(scenario):
    path = require_shared("specs", scenario, f"{scenario}.yaml")
    m = load_mapping(path)
    inputs, outputs = _spec_props(path.with_suffix(".slugsin").read_text())
    issues = check_mapping(m, inputs, outputs)
    assert [i for i in issues if i.severity == "error"] == [], issues
    assert m.scenario_namespace() == ("spheros" if scenario.startswith("spheros") else scenario)
    in_topics, out_topics = resolve_topics(m, inputs, outputs, m.scenario_namespace())
    ns = m.scenario_namespace()
    assert all(t == f"/{ns}/inputs/{p}" for p, t in in_topics.items()), in_topics
    assert all(ts == [f"/{ns}/outputs/{p}"] for p, ts in out_topics.items()), out_topics


def test_spheros_outputs_map_to_one_node_per_robot():
    m = load_mapping(require_shared("specs", "spheros", "spheros.yaml"))
    nodes = [e.node for e in m.outputs["move_left"]]
    assert nodes == [f"/spheros/outputs/{r}/move_left" for r in ("sphero_ggw", "sphero_wpp", "sphero_rgw",
                                                                  "sphero_wpw")], nodes
    assert m.outputs["move_left"][0].parameters == {"publish_topic": "/sphero_ggw/cmd_vel", "vx": -35}


def test_tutorial_output_without_node_is_a_warning_with_its_line():
    m = load_mapping(require_shared("specs", "tutorial", "tutorial.yaml"))
    got = issue_texts(m, ["person", "sense_object"], ["stop_camera", "move", "stop"])
    assert got == [f"{m.file}:19: warning: output 'stop_camera' has no entry with a 'node'; it is treated as "
                   "unmapped and the executor uses its default topic"], got
    assert shared_dir() is not None


def _essence(m):
    return {kind: {p: [(e.node, e.topic, e.pkg, e.filename, e.type, e.args, e.parameters) for e in es]
                   for p, es in section.items()}
            for kind, section in (("inputs", m.inputs), ("outputs", m.outputs))}, m.namespace


@pytest.mark.parametrize("scenario", ["simple", "tutorial", "firefighting", "move_group_and_move_base",
                                      "spheros", "spheros_problem"])
def test_format_mapping_round_trips_the_thesis_mappings(scenario):
    m = load_mapping(require_shared("specs", scenario, f"{scenario}.yaml"))
    again = parse_mapping(format_mapping(m), "again.yaml")
    assert _essence(again) == _essence(m)


ENTRY = st.fixed_dictionaries({"node": NAMES.map(lambda n: f"/ns/{n}")},
                              optional={"pkg": NAMES, "filename": NAMES.map(lambda n: n + ".py"), "args": NAMES,
                                        "parameters": st.dictionaries(NAMES, st.integers() | st.booleans()
                                                                      | NAMES | st.floats(allow_nan=False),
                                                                      min_size=1, max_size=3)})


@given(st.dictionaries(NAMES, st.lists(ENTRY, max_size=3), max_size=4), st.none() | NAMES)
def test_format_mapping_round_trips_any_mapping(outputs, namespace):
    data = {"outputs": {p: es if len(es) != 1 else es[0] for p, es in outputs.items()}}
    if namespace:
        data["namespace"] = namespace
    m = parse_mapping(yaml.safe_dump(data), "gen.yaml")
    assert _essence(parse_mapping(format_mapping(m), "again.yaml")) == _essence(m)


def test_a_proposition_written_twice_is_one_proposition_with_both_nodes():
    """The thesis' mapping GUI writes one block per row: Fig. 3.9's accidental mapping of the 'drop node'
    to pickup is the key pickup twice. Both nodes are pickup's, for the analysis to find (E3)."""
    mapping = parse_mapping("outputs:\n  pickup:\n    node: /pickup\n  drop:\n    node: /drop\n"
                            "  pickup:\n    node: /drop\n", "fig39.yaml")
    assert [e.node for e in mapping.outputs["pickup"]] == ["/pickup", "/drop"]
    assert [e.line for e in mapping.outputs["pickup"]] == [3, 7]
    assert mapping.lines[("output", "pickup")] == 2



def test_expected_feedback_is_read_checked_and_written_back():
    text = "expected_feedback:\n  stop: '*_rc'\n  topLane: [topLane_rc, leftLane_rc]\noutputs:\n  stop:\n    node: s\n"
    mapping = parse_mapping(text, "m.yaml")
    assert mapping.expected_feedback == [("stop", "*_rc", 2), ("topLane", "topLane_rc", 3),
                                         ("topLane", "leftLane_rc", 3)]
    again = parse_mapping(format_mapping(mapping), "again.yaml")
    assert [p[:2] for p in again.expected_feedback] == [p[:2] for p in mapping.expected_feedback]
    with pytest.raises(MappingError) as err:
        parse_mapping("expected_feedback:\n  stop: 3\n", "bad.yaml")
    assert "bad.yaml:2" in str(err.value) and "must name an input" in str(err.value)


def test_a_node_names_its_robot_and_keeps_it_through_format():
    m = parse_mapping("outputs:\n  b:\n    - {node: r1_b, robot: r1}\n    - {node: shared_b}\n", "m.yaml")
    assert [e.robot for e in m.outputs["b"]] == ["r1", None]
    again = parse_mapping(format_mapping(m), "again.yaml")
    assert [e.robot for e in again.outputs["b"]] == ["r1", None]

"""generate_launch: the roslaunch XML made from a mapping (parsed back with lxml, no ROS needed)."""
from __future__ import annotations

import json
import posixpath
import textwrap

import pytest
from helpers import require_shared
from hypothesis import given, settings
from hypothesis import strategies as st
from lxml import etree as ET

from ltl_stack.runtime.config.launch import LaunchError, generate_launch, main, package_relative
from ltl_stack.runtime.config.mapping import load_mapping, parse_mapping

MAPPING = textwrap.dedent("""\
    inputs:
      person:
        node: 'person'
        node_publish_topic: '/demo/inputs/person'
        pkg: 'controller_executor'
        filename: 'scripts/get_tag.py'
        parameters:
          tag_no: 5
          enabled: true
          gain: 0.5
          label: '--x'
    outputs:
      move:
        - node: '/demo/outputs/r1/move'
          node_subscribe_topic: '/demo/outputs/move'
          pkg: 'ltl_stack'
          type: 'set_velocity'
          args: '--verbose'
          parameters:
            publish_topic: '/r1/cmd_vel'
            limits: [1, 2]
        - node: '/demo/outputs/r2/move'
          node_subscribe_topic: '/demo/outputs/move'
          pkg: 'ltl_stack'
          filename: 'set_velocity'
      stop:
        node_subscribe_topic: '/demo/outputs/stop'
    """)


def launch_tree(text=MAPPING, **kwargs):
    kwargs.setdefault("spec_path", "/specs/demo.slugsin")
    kwargs.setdefault("namespace", "demo")
    result = generate_launch(parse_mapping(text, "demo.yaml"), **kwargs)
    return result, ET.fromstring(result.xml.encode())


def nodes_by_name(root, base="/"):
    """Full node name -> (enclosing group, node element), resolving nested group namespaces as roslaunch
    does (a relative ns in the enclosing one, an absolute one as it is); the file runs in ``base``."""
    found = {}

    def walk(element, ns):
        for child in element:
            if child.tag == "group":
                inner = child.get("ns")
                walk(child, ns if inner is None else inner if inner.startswith("/") else posixpath.join(ns, inner))
            elif child.tag == "node":
                found[posixpath.join(ns, child.get("name"))] = (element, child)

    walk(root, base)
    return found


def test_nodes_land_in_their_groups_with_type_params_and_remap():
    result, root = launch_tree()
    nodes = nodes_by_name(root)
    assert sorted(nodes) == ["/demo/controller_executor", "/demo/outputs/r1/move", "/demo/outputs/r2/move",
                             "/demo/person"], sorted(nodes)
    group, person = nodes["/demo/person"]
    assert group.get("if") == "$(arg start_inputs)"
    assert (person.get("pkg"), person.get("type")) == ("controller_executor", "get_tag.py")
    assert [(r.get("from"), r.get("to")) for r in person.findall("remap")] == [("proposition", "/demo/inputs/person")]
    params = {p.get("name"): (p.get("type"), p.get("value")) for p in person.findall("param")}
    assert params == {"tag_no": ("int", "5"), "enabled": ("bool", "true"), "gain": ("double", "0.5"),
                      "label": ("str", "--x")}, params
    _, r1 = nodes["/demo/outputs/r1/move"]
    assert (r1.get("type"), r1.get("args")) == ("set_velocity", "--verbose"), r1.attrib
    assert r1.find("rosparam").get("param") == "limits" and r1.find("rosparam").text == "[1, 2]"
    group, executor = nodes["/demo/controller_executor"]
    assert group.get("ns") == "demo" and executor.get("if") == "$(arg start_executor)"
    assert executor.get("required") == "true", executor.attrib
    assert executor.get("args") == "$(arg spec) $(arg mapping) $(arg executor_args)"
    args = {a.get("name"): a.get("default") for a in root.findall("arg")}
    assert args["spec"] == "/specs/demo.slugsin" and args["start_executor"] == "true", args
    assert result.skipped == ["demo.yaml:27: output 'stop': entry without 'node'"], result.skipped
    assert [n["node"] for n in result.nodes] == ["/demo/person", "/demo/outputs/r1/move", "/demo/outputs/r2/move"]


RELATIVE = textwrap.dedent("""\
    inputs:
      person:
        node: 'person'
        pkg: 'ltl_stack'
        filename: 'topic_threshold_sensor'
        parameters: {sensor_topic: 'camera/person_distance'}
    outputs:
      move:
        - node: 'move'
          pkg: 'ltl_stack'
          filename: 'set_velocity'
          parameters: {publish_topic: 'cmd_vel'}
        - node: 'arm/move'
          node_subscribe_topic: 'move'
          pkg: 'ltl_stack'
          filename: 'publish_on_edge'
    """)


@pytest.mark.parametrize("base", ["/", "/robot1/"])
def test_relative_mappings_give_a_relocatable_scenario(base):
    result, root = launch_tree(RELATIVE, namespace="lab")
    assert root.find("group").get("ns") == "lab"  # relative: an enclosing <group ns> moves everything
    nodes = nodes_by_name(root, base)
    prefix = base.rstrip("/")
    assert sorted(nodes) == [f"{prefix}/lab/{n}" for n in ("arm/move", "controller_executor", "move", "person")]
    remaps = {name: node.find("remap").get("to") for name, (_, node) in nodes.items() if node.find("remap") is not None}
    # Relative remaps resolve in the node's namespace: /robot1/lab/ + inputs/person
    assert remaps[f"{prefix}/lab/person"] == "inputs/person" and remaps[f"{prefix}/lab/move"] == "outputs/move"
    # A node below the scenario cannot name outputs/move relatively: absolute, and said so.
    assert remaps[f"{prefix}/lab/arm/move"] == "/lab/outputs/move"
    assert any("arm/move cannot name its topic outputs/move relatively" in w for w in result.warnings), result.warnings


HOSTILE = ["<", "&", '"', "'", "]]>", "a<b>&amp;\"'c", "-->", "<!-- x -->", "$(env HOME)", "--", "x-", "\u00e9\u4e2d"]


@pytest.mark.parametrize("value", HOSTILE)
def test_hostile_values_still_give_well_formed_xml_that_keeps_them(value, tmp_path):
    mapping = {"inputs": {"person": {"node": "person", "pkg": "ltl_stack", "filename": "region_sensor",
                                     "args": value, "parameters": {"region": value, "list": [value],
                                                                   "nested": {"k": value}}}}}
    import yaml

    text = yaml.safe_dump(mapping)
    result = generate_launch(parse_mapping(text, value + ".yaml"), spec_path=None, namespace="lab")
    root = ET.fromstring(result.xml.encode())  # raises on anything that is not well-formed
    _, node = nodes_by_name(root)["/lab/person"]
    assert node.get("args") == value
    by_name = {p.get("param") or p.get("name"): p for p in node if p.tag in ("param", "rosparam")}
    region = by_name["region"]
    if "$(" in value:  # roslaunch would substitute it in a <param value>: rosparam without substitution
        assert region.tag == "rosparam" and region.get("subst_value") == "false"
        assert yaml.safe_load(region.text) == value
    else:
        assert region.get("value") == value
    assert yaml.safe_load(by_name["list"].text) == [value]
    assert yaml.safe_load(by_name["nested"].text) == {"k": value}


@settings(max_examples=60, deadline=None)
@given(st.text(alphabet=st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=12))
def test_any_parameter_text_is_well_formed_or_refused(value):
    import yaml

    text = yaml.safe_dump({"inputs": {"p": {"node": "p", "pkg": "x", "filename": "y", "parameters": {"v": value}}}})
    try:
        result = generate_launch(parse_mapping(text, "m.yaml"), spec_path=None, namespace="lab")
    except LaunchError as err:
        assert "control character" in str(err), err
        return
    ET.fromstring(result.xml.encode())


def test_control_characters_and_bad_parameter_names_are_refused():
    for text, fragment in (('inputs: {p: {node: p, pkg: x, filename: y, parameters: {v: "a\\x01b"}}}', "control"),
                           ("inputs: {p: {node: p, pkg: x, filename: y, parameters: {'a b': 1}}}",
                            "parameter name 'a b' is not a legal ROS name")):
        with pytest.raises(LaunchError, match=fragment):
            generate_launch(parse_mapping(text, "m.yaml"), spec_path=None, namespace="lab")


def test_output_that_is_an_input_is_refused_and_nothing_is_written(tmp_path, capsys):
    mapping = tmp_path / "demo.yaml"
    mapping.write_text(MAPPING)
    before = mapping.read_text()
    link = tmp_path / "link.yaml"
    link.symlink_to(mapping)
    for out in (mapping, link):
        assert main([str(mapping), "-o", str(out)]) == 2
        assert "output would overwrite the input" in capsys.readouterr().err
    assert mapping.read_text() == before


def test_spec_checks_reject_unknown_propositions_before_writing():
    with pytest.raises(LaunchError, match="demo.yaml:2: input 'person' is not a proposition"):
        launch_tree(propositions=(["human"], ["move", "stop"]))


def test_two_entries_with_one_node_name_are_an_error():
    text = MAPPING.replace("/demo/outputs/r2/move", "/demo/outputs/r1/move")
    with pytest.raises(LaunchError, match=r"demo.yaml:22: node /demo/outputs/r1/move of output 'move' is also"):
        launch_tree(text)


def test_without_spec_the_executor_is_off_by_default():
    _, root = launch_tree(spec_path=None)
    args = {a.get("name"): a.get("default") for a in root.findall("arg")}
    assert args["start_executor"] == "false", args


@pytest.mark.parametrize("scenario", ["simple", "tutorial", "firefighting", "move_group_and_move_base",
                                      "spheros", "spheros_problem"])
def test_every_thesis_mapping_becomes_a_launch_file(scenario, tmp_path, capsys):
    mapping = require_shared("specs", scenario, f"{scenario}.yaml")
    out = tmp_path / f"{scenario}.launch"
    assert main([str(mapping), "-o", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    root = ET.parse(str(out)).getroot()
    nodes = nodes_by_name(root)
    m = load_mapping(mapping)
    expected = sum(1 for e in m.entries() if e.node)
    assert len(summary["nodes"]) == expected and len(nodes) == expected + 1, (summary["nodes"], sorted(nodes))
    ns = m.scenario_namespace()
    assert f"/{ns}/controller_executor" in nodes


def test_spheros_output_starts_one_node_per_robot(tmp_path):
    out = tmp_path / "s.launch"
    assert main([str(require_shared("specs", "spheros", "spheros.yaml")), "-o", str(out)]) == 0
    nodes = nodes_by_name(ET.parse(str(out)).getroot())
    robots = sorted(name.split("/")[3] for name in nodes if name.endswith("/move_left"))
    assert robots == ["sphero_ggw", "sphero_rgw", "sphero_wpp", "sphero_wpw"], robots
    _, node = nodes["/spheros/outputs/sphero_ggw/move_left"]
    assert node.find("remap").get("to") == "/spheros/outputs/move_left"


ROBOTS = textwrap.dedent("""\
    inputs:
      person: {node: person, pkg: ltl_stack, type: topic_threshold_sensor}
      r1_here: {node: r1_here, pkg: ltl_stack, type: topic_threshold_sensor, robot: r1}
    outputs:
      move:
        - {node: r1_move, pkg: ltl_stack, type: set_velocity, robot: r1}
        - {node: r2_move, pkg: ltl_stack, type: set_velocity, robot: r2}
        - {node: shared_move, pkg: ltl_stack, type: set_velocity}
    """)


def test_nodes_naming_a_robot_start_with_that_robot_and_the_others_with_start_shared():
    result, root = launch_tree(ROBOTS)
    args = {a.get("name"): a.get("default") for a in root.iter("arg")}
    assert args["robots"] == "r1 r2" and args["start_shared"] == "true", args
    conditions = {name: group.get("if") for name, (group, _) in nodes_by_name(root).items()
                  if not name.endswith("/controller_executor")}
    assert conditions == {
        "/demo/person": "$(eval start_inputs and start_shared)",
        "/demo/r1_here": "$(eval start_inputs and 'r1' in str(robots).split())",
        "/demo/r1_move": "$(eval start_outputs and 'r1' in str(robots).split())",
        "/demo/r2_move": "$(eval start_outputs and 'r2' in str(robots).split())",
        "/demo/shared_move": "$(eval start_outputs and start_shared)"}, conditions
    assert {n["node"]: n["robot"] for n in result.nodes}["/demo/r2_move"] == "r2"


def test_a_mapping_without_robots_has_no_robot_arguments():
    _, root = launch_tree()
    assert not {"robots", "start_shared"} & {a.get("name") for a in root.iter("arg")}


def test_cli_errors_exit_2_and_write_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("inputs:\n  a:\n    nodes: x\n")
    out = tmp_path / "out.launch"
    assert main([str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"generate_launch: error: {bad}:3: input 'a': unknown key 'nodes'" in err and "Traceback" not in err, err
    assert not out.exists() and list(tmp_path.iterdir()) == [bad]
    assert main([str(tmp_path / "missing.yaml")]) == 2
    assert "missing.yaml: no such file" in capsys.readouterr().err


def test_an_existing_file_is_replaced_whole(tmp_path):
    mapping = tmp_path / "demo.yaml"
    mapping.write_text(MAPPING)
    out = tmp_path / "demo.launch"
    out.write_text("old")
    assert main([str(mapping), "-o", str(out)]) == 0
    assert out.read_text().startswith('<?xml version="1.0"?>')
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo.launch", "demo.yaml"]


def test_paths_inside_a_package_are_written_with_find(tmp_path):
    pkg = tmp_path / "my_robot"
    (pkg / "config").mkdir(parents=True)
    (pkg / "package.xml").write_text('<?xml version="1.0"?><package format="3"><name>my_robot</name></package>')
    spec = pkg / "config" / "task.slugsin"
    spec.write_text("")
    assert package_relative(spec) == "$(find my_robot)/config/task.slugsin"
    outside = tmp_path / "elsewhere.slugsin"
    outside.write_text("")
    assert package_relative(outside) == str(outside.resolve())

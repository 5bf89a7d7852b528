"""generate_launch: the roslaunch XML made from a mapping (parsed back, no ROS needed)."""
from __future__ import annotations

import json
import textwrap
import xml.etree.ElementTree as ET

import pytest
from helpers import require_shared

from ltl_stack.ros.launch_gen import LaunchError, generate_launch, main
from ltl_stack.runtime.mapping import load_mapping, parse_mapping

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
    return result, ET.fromstring(result.xml.split("\n", 1)[1])


def nodes_by_name(root):
    """Full node name -> node element, resolving the group namespaces."""
    found = {}
    for group in root.iter("group"):
        for node in group.findall("node"):
            found[f"{group.get('ns').rstrip('/')}/{node.get('name')}"] = (group, node)
    return found


def test_nodes_land_in_their_groups_with_type_params_and_remap():
    result, root = launch_tree()
    nodes = nodes_by_name(root)
    assert sorted(nodes) == ["/demo/controller_executor", "/demo/inputs/person", "/demo/outputs/r1/move",
                             "/demo/outputs/r2/move"], sorted(nodes)
    group, person = nodes["/demo/inputs/person"]
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
    assert group.get("if") == "$(arg start_executor)"
    assert executor.get("args") == "$(arg spec) $(arg mapping) --namespace demo $(arg executor_args)"
    args = {a.get("name"): a.get("default") for a in root.findall("arg")}
    assert args["spec"] == "/specs/demo.slugsin" and args["start_executor"] == "true", args
    assert result.skipped == ["demo.yaml:27: output 'stop': entry without 'node'"], result.skipped
    assert [n["node"] for n in result.nodes] == ["/demo/inputs/person", "/demo/outputs/r1/move",
                                                 "/demo/outputs/r2/move"]


def test_spec_checks_reject_unknown_propositions_before_writing():
    with pytest.raises(LaunchError, match="demo.yaml:2: error: input 'person' is not a proposition"):
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
    root = ET.parse(out).getroot()
    nodes = nodes_by_name(root)
    m = load_mapping(mapping)
    expected = sum(1 for e in m.entries() if e.node)
    assert len(summary["nodes"]) == expected and len(nodes) == expected + 1, (summary["nodes"], sorted(nodes))
    ns = m.scenario_namespace()
    assert f"/{ns}/controller_executor" in nodes


def test_spheros_output_starts_one_node_per_robot(tmp_path):
    out = tmp_path / "s.launch"
    assert main([str(require_shared("specs", "spheros", "spheros.yaml")), "-o", str(out)]) == 0
    nodes = nodes_by_name(ET.parse(out).getroot())
    robots = sorted(name.split("/")[3] for name in nodes if name.endswith("/move_left"))
    assert robots == ["sphero_ggw", "sphero_rgw", "sphero_wpp", "sphero_wpw"], robots
    _, node = nodes["/spheros/outputs/sphero_ggw/move_left"]
    assert node.find("remap").get("to") == "/spheros/outputs/move_left"


def test_cli_errors_exit_2_and_write_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("inputs:\n  a:\n    nodes: x\n")
    out = tmp_path / "out.launch"
    assert main([str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:3: input 'a': unknown key 'nodes'" in err and "Traceback" not in err, err
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
    from ltl_stack.ros.launch_gen import package_relative

    pkg = tmp_path / "my_robot"
    (pkg / "config").mkdir(parents=True)
    (pkg / "package.xml").write_text('<?xml version="1.0"?><package format="3"><name>my_robot</name></package>')
    spec = pkg / "config" / "task.slugsin"
    spec.write_text("")
    assert package_relative(spec) == "$(find my_robot)/config/task.slugsin"
    outside = tmp_path / "elsewhere.slugsin"
    outside.write_text("")
    assert package_relative(outside) == str(outside.resolve())

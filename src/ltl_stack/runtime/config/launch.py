"""``generate_launch MAPPING [-o FILE]``: a roslaunch file for a proposition mapping. ROS-free.

The launch file starts every proposition node of the mapping (thesis §3.5.1, Fig. 3.2) with its
``parameters`` as private parameters, and the controller executor, all inside one *relative*
``<group ns="<scenario>">``, so that including the file in ``<group ns="robot1">`` puts every node,
topic, parameter and service of the scenario under ``/robot1`` and two copies can run side by side.
Relative node names live in the scenario's namespace, relative proposition topics in its ``inputs``
and ``outputs`` groups; each node's relative topic ``proposition`` is remapped to its proposition
topic (what ``ltl_stack.ros.proposition_node`` nodes read). The executor is ``required``: when it
exits (unrealizable spec, bad file) roslaunch stops the whole scenario instead of leaving robots
driving. A ``filename`` such as ``get_tag.py`` becomes the node ``type`` (``type:`` overrides it).

Launch arguments: ``spec``, ``mapping``, ``start_executor``, ``start_inputs``, ``start_outputs``,
``executor_args`` (extra executor flags, e.g. ``--on-violation all-false``). When node entries name
their ``robot:``, also ``robots`` (the robots whose nodes start here, space-separated; default all)
and ``start_shared`` (the nodes of no robot), so that each robot's host starts that robot's nodes:
``robots:=r1 start_shared:=false start_executor:=false`` there, ``robots:=none`` on the controller's.

Every value is escaped, so the output is well-formed XML whatever the mapping holds; values XML
cannot carry at all (control characters) are refused, and a string parameter holding ``$(`` goes
through ``<rosparam>``, which roslaunch does not substitute.
"""
from __future__ import annotations

import posixpath
import re
import sys
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape, quoteattr

import yaml

from ltl_stack import cli
from ltl_stack.errors import Exit, UserError
from ltl_stack.runtime.config.mapping import (
    INPUT,
    Mapping,
    MappingError,
    NodeEntry,
    check_mapping,
    load_mapping,
    misfit,
)
from ltl_stack.runtime.config.ros_names import (
    check_proposition_names,
    is_legal_base_name,
    is_legal_name,
    load_spec_for_ros,
)

PROG = "generate_launch"
#: Characters XML 1.0 cannot hold, escaped or not.
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ufffe\uffff]")


class LaunchError(UserError):
    """A mapping that cannot become a launch file; the message names file, line and node."""


@dataclass
class LaunchResult:
    xml: str
    nodes: list[dict[str, Any]] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def scenario_relative(name: str | None, kind: str, proposition: str) -> str:
    """A mapping topic relative to the scenario's namespace (``inputs/<p>`` by default), or absolute."""
    group = "inputs" if kind == INPUT else "outputs"
    if not name:
        return f"{group}/{proposition}"
    return posixpath.normpath(name) if name.startswith("/") else posixpath.normpath(f"{group}/{name}")


def node_relative(name: str) -> str:
    """A mapping node name relative to the scenario's namespace (or absolute)."""
    return posixpath.normpath(name)


def remap_target(topic: str, node_ns: str, namespace: str) -> tuple[str, bool]:
    """The remap ``to`` of a node in ``node_ns`` (scenario-relative, "" for the scenario itself) for a
    scenario-relative or absolute ``topic``, and whether it stays relative (relocatable)."""
    if topic.startswith("/") or node_ns.startswith("/"):
        absolute = topic if topic.startswith("/") else posixpath.join("/", namespace, topic)
        return absolute, topic.startswith("/")
    if not node_ns:
        return topic, True
    if topic.startswith(node_ns + "/"):
        return topic[len(node_ns) + 1:], True
    return posixpath.join("/", namespace, topic), False


def generate_launch(mapping: Mapping, *, spec_path: str | None, namespace: str,
                    propositions: tuple[Sequence[str], Sequence[str]] | None = None,
                    executor: bool = True) -> LaunchResult:
    """The launch XML for ``mapping``. ``propositions`` (inputs, outputs) enables the spec checks."""
    namespace = namespace.strip("/")
    if not namespace or not is_legal_name(namespace):
        raise LaunchError(f"scenario namespace {namespace!r} is not a legal ROS name")
    result = LaunchResult(xml="")
    check_proposition_names([*mapping.inputs, *mapping.outputs], mapping.file)
    if propositions is not None:
        issues = check_mapping(mapping, *propositions)
        error = misfit(issues)
        if error is not None:
            raise LaunchError(str(error))
        result.warnings += [str(i) for i in issues if i.severity != "error"]
    groups: dict[tuple[str, str | None, str], list[tuple[NodeEntry, str, str]]] = {}
    seen: dict[str, NodeEntry] = {}
    unstarted: list[tuple[str, str]] = []
    for entry in mapping.entries():
        where = f"{mapping.file}:{entry.line}"
        if entry.node is None:
            result.skipped.append(f"{where}: {entry.kind} {entry.proposition!r}: entry without 'node'")
            continue
        name = node_relative(entry.node)
        if not entry.pkg or not entry.executable:
            unstarted.append((name, f"{where}: {entry.kind} {entry.proposition!r}: node {name} has no "
                                    "pkg/filename; start it yourself"))
            continue
        if name in seen:
            raise LaunchError(f"{where}: node {name} of {entry.kind} {entry.proposition!r} is also the node of "
                              f"{seen[name].kind} {seen[name].proposition!r} (line {seen[name].line}); "
                              "roslaunch needs distinct node names")
        seen[name] = entry
        _check_entry(entry, where)
        parent, base = posixpath.split(name)
        topic = scenario_relative(entry.topic, entry.kind, entry.proposition)
        to, relocatable = remap_target(topic, parent, namespace)
        if not relocatable:
            result.warnings.append(f"{where}: {entry.kind} {entry.proposition!r}: node {name} cannot name its "
                                   f"topic {topic} relatively (ROS resolves relative names only downwards); "
                                   f"written as {to}, which does not move with an enclosing namespace")
        groups.setdefault((entry.group, entry.robot, parent), []).append((entry, base, to))
        full_node = name if name.startswith("/") else f"/{namespace}/{name}"
        full_topic = topic if topic.startswith("/") else f"/{namespace}/{topic}"
        result.nodes.append({"proposition": entry.proposition, "kind": entry.kind, "node": full_node,
                             "pkg": entry.pkg, "type": entry.executable, "topic": full_topic,
                             "robot": entry.robot})
    # An entry without pkg naming a node another entry starts (an action node publishing its completion
    # input) is started by that entry.
    result.skipped += [text for name, text in unstarted if name not in seen]
    result.warnings += result.skipped

    lines = ['<?xml version="1.0"?>',
             f"<!-- Generated by generate_launch from {_comment(mapping.file)}. Regenerate rather than edit. -->",
             "<launch>",
             f'  <arg name="spec" default={_attr(package_relative(spec_path) if spec_path else "")}/>',
             f'  <arg name="mapping" default={_attr(package_relative(mapping.file))}/>',
             f'  <arg name="start_executor" default="{"true" if executor and spec_path else "false"}"/>',
             '  <arg name="start_inputs" default="true"/>',
             '  <arg name="start_outputs" default="true"/>',
             '  <arg name="executor_args" default=""/>']
    robots = list(dict.fromkeys(robot for _, robot, _ in groups if robot))
    if robots:
        lines += [f'  <arg name="robots" default={_attr(" ".join(robots))}',
                  '       doc="the robots whose nodes start here (space-separated; none: no robot)"/>',
                  '  <arg name="start_shared" default="true" doc="start the nodes of no robot"/>']
    lines += ["", f"  <group ns={_attr(namespace)}>"]
    for (group, robot, parent), members in groups.items():
        cond = _condition(group, robot, bool(robots))
        lines.append(f"    <group ns={_attr(parent)} {cond}>" if parent else f"    <group {cond}>")
        for entry, base, topic in members:
            lines += _node_xml(entry, base, topic, indent="      ")
        lines.append("    </group>")
    for text in result.skipped:
        lines.append(f"    <!-- not started: {_comment(text)} -->")
    lines += ["",
              "    <!-- the controller: it takes this group's namespace as the scenario's; when it exits, the",
              "         whole launch stops -->",
              '    <node name="controller_executor" pkg="ltl_stack" type="controller_executor" output="screen"',
              '          required="true" if="$(arg start_executor)" args="$(arg spec) $(arg mapping) '
              '$(arg executor_args)"/>',
              "  </group>",
              "</launch>", ""]
    result.xml = "\n".join(lines)
    return result


def _condition(group: str, robot: str | None, by_robot: bool) -> str:
    """The ``if`` of a group of nodes: its kind started and, in a mapping naming robots, its robot
    among ``robots`` (a robot name is a ROS base name: nothing to quote) or, for no robot, ``start_shared``."""
    if not by_robot:
        return f'if="$(arg start_{group})"'
    if robot is None:
        return f'if="$(eval start_{group} and start_shared)"'
    return f'if="$(eval start_{group} and {robot!r} in str(robots).split())"'


def _check_entry(entry: NodeEntry, where: str) -> None:
    """Refuse what no launch file can carry: control characters, parameter names that are not ROS names."""
    texts = [entry.node or "", entry.pkg or "", entry.executable or "", entry.args or "", entry.topic or ""]
    for key, value in entry.parameters.items():
        if not is_legal_base_name(key):
            raise LaunchError(f"{where}: {entry.kind} {entry.proposition!r}: parameter name {key!r} is not a "
                              "legal ROS name (letters, digits and _, starting with a letter)")
        texts.append(yaml.safe_dump(value) if not isinstance(value, str) else value)
    for text in texts:
        if _NOT_XML.search(text):
            raise LaunchError(f"{where}: {entry.kind} {entry.proposition!r}: {text!r} holds a control character "
                              "that XML cannot carry")


def package_relative(path: str | Path) -> str:
    """``$(find pkg)/rel/path`` when ``path`` lies inside a ROS package, else the absolute path.

    Launch files that name their files this way keep working in another clone or an install space.
    """
    absolute = Path(path).resolve()
    for folder in absolute.parents:
        manifest = folder / "package.xml"
        if manifest.is_file():
            try:
                name = (ET.parse(manifest).getroot().findtext("name") or "").strip()
            except ET.ParseError:
                name = ""
            if name and is_legal_base_name(name):
                return f"$(find {name})/{absolute.relative_to(folder).as_posix()}"
    return str(absolute)


def _attr(value: str) -> str:
    if _NOT_XML.search(value):
        raise LaunchError(f"{value!r} holds a control character that XML cannot carry")
    return quoteattr(value)


def _node_xml(entry: NodeEntry, name: str, topic: str, indent: str) -> list[str]:
    attrs = f"name={_attr(name)} pkg={_attr(entry.pkg)} type={_attr(entry.executable)}"
    if entry.args:
        attrs += f" args={_attr(entry.args)}"
    out = [f"{indent}<!-- {entry.kind} {_comment(entry.proposition)} -->",
           f"{indent}<node {attrs}>",
           f'{indent}  <remap from="proposition" to={_attr(topic)}/>']
    for key, value in entry.parameters.items():
        out.append(indent + "  " + _param_xml(key, value))
    out.append(f"{indent}</node>")
    return out


def _param_xml(key: str, value: Any) -> str:
    name = _attr(key)
    if value is None:
        return f"<!-- parameter {_comment(key)} has no value -->"
    if isinstance(value, bool):
        return f'<param name={name} type="bool" value="{"true" if value else "false"}"/>'
    if isinstance(value, int):
        return f'<param name={name} type="int" value="{value}"/>'
    if isinstance(value, float):
        return f'<param name={name} type="double" value={_attr(repr(value))}/>'
    if isinstance(value, str) and "$(" not in value:
        return f'<param name={name} type="str" value={_attr(value)}/>'
    # Lists, dicts, and strings roslaunch would substitute ($(...)): rosparam without substitution.
    text = yaml.safe_dump(value, default_flow_style=True, width=1 << 30).strip()
    if text.endswith("\n...") or text.endswith("..."):
        text = text.rsplit("\n...", 1)[0].strip()
    return f'<rosparam param={name} subst_value="false">{escape(text)}</rosparam>'


def _comment(text: str) -> str:
    """Text that can stand inside ``<!-- -->``: no ``--``, no control characters, not ending in ``-``."""
    cleaned = _NOT_XML.sub("?", str(text)).replace("--", "- -")
    return cleaned + " " if cleaned.endswith("-") else cleaned


def build_parser() -> cli.ToolParser:
    parser = cli.ToolParser(
        prog=PROG,
        description="Write a roslaunch file that starts every proposition node of a mapping YAML "
                    "(with its parameters) and the controller executor, in one relative scenario namespace.",
        exit_codes=(Exit.OK, Exit.BAD_INPUT, Exit.WRITE_FAILED))
    parser.add_argument("mapping", help="proposition mapping YAML")
    parser.add_argument("-o", "--output", metavar="FILE", help="launch file to write (default: standard output)")
    parser.add_argument("--spec", help="specification the executor runs and the mapping is checked against "
                                       "(default: the mapping's name with .slugsin, when that file exists)")
    parser.add_argument("--namespace", help="scenario namespace (default: from the mapping's topics, else the "
                                            "mapping's file name)")
    parser.add_argument("--no-executor", action="store_true", help="start only the proposition nodes")
    parser.add_json("a summary (nodes, warnings, and the launch XML when there is no -o)")
    return parser


def _generate(args: Any) -> int:
    spec_path = args.spec
    if spec_path is None:
        guess = Path(args.mapping).with_suffix(".slugsin")
        spec_path = str(guess) if guess.is_file() else None
    cli.check_outputs([args.mapping, spec_path], [args.output])
    try:
        mapping = load_mapping(args.mapping)
    except MappingError as err:
        raise LaunchError(str(err)) from None
    propositions = None
    if spec_path:
        spec = load_spec_for_ros(spec_path, LaunchError)
        propositions = (spec.inputs, spec.outputs)
        spec_path = str(Path(spec_path).resolve())
    elif not args.no_executor:
        cli.warn(PROG, "no spec given (--spec) and none found beside the mapping; the executor is off by default "
                       "(start_executor:=true spec:=...)")
    namespace = (args.namespace or mapping.scenario_namespace() or Path(args.mapping).stem).strip("/")
    result = generate_launch(mapping, spec_path=spec_path, namespace=namespace, propositions=propositions,
                             executor=not args.no_executor)
    if args.output:
        cli.write_output(args.output, result.xml, "launch file")
    for warning in result.warnings:
        cli.warn(PROG, warning)
    if args.json:
        summary = {"output": args.output, "namespace": namespace, "spec": spec_path, "nodes": result.nodes,
                   "warnings": result.warnings}
        if not args.output:
            summary["launch"] = result.xml
        cli.print_json(summary)
    elif not args.output:
        sys.stdout.write(result.xml)
    else:
        cli.say(PROG, f"wrote {args.output}: {len(result.nodes)} proposition nodes"
                      f"{' and the executor' if spec_path and not args.no_executor else ''}")
    return Exit.OK


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return cli.run(PROG, lambda: _generate(args))


__all__ = ["LaunchError", "LaunchResult", "generate_launch", "main", "package_relative", "remap_target"]

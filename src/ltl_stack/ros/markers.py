"""``map_markers``: the region map, the robot's region and the proposition values for RViz.

Two ``visualization_msgs/MarkerArray`` topics, both latched:

- ``region_markers``: each region of the scenario's ``.regions`` map outlined, filled grey, with its
  name — published once at start-up (a map does not change; 10,000 regions cost nothing per tick);
- ``markers``: what changes — the robot's region filled green (``localized_region``, else the
  controller's ``R_rc`` inputs), the regions the controller heads for (a true output named as the
  region) orange, and a text block with the controller's state, goal, mode and true propositions (from
  its ``~state``); on every change and every 1/``~rate`` s, its work bounded by the propositions and
  the highlighted regions, not by the size of the map. It starts with a DELETEALL, so a region no
  longer highlighted goes back to grey.

A ControllerState that cannot be read (keys and values of different lengths, from any publisher) is
logged once per publisher and ignored: the view keeps the last state it could read. The shapes are
computed ROS-free in ``ltl_stack.runtime.runs.map_view``; the map is validated as every reader validates it
(``ltl_stack.spec.region_map.check_regions``).
"""
from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Any

import rospy
from geometry_msgs.msg import Point as PointMsg
from std_msgs.msg import ColorRGBA, String

from ltl_stack.msg import ControllerState
from ltl_stack.ros.localization import MAP_PARAMS, load_map
from ltl_stack.ros.master import read_param
from ltl_stack.ros.proposition_node import NodeSpec, Param, run_node
from ltl_stack.ros.valuation import state_valuations
from ltl_stack.runtime.config.node_params import Bound
from ltl_stack.runtime.propositions.regions import RegionMap
from ltl_stack.runtime.runs.map_view import (
    CURRENT,
    HEADING,
    heading_regions,
    region_from_inputs,
    region_shapes,
    valuation_text,
)

MAP_MARKERS = NodeSpec(
    name="map_markers",
    kind="view",
    description="RViz markers (visualization_msgs/MarkerArray): the region map once on region_markers; on "
                "markers the robot's region, the regions the controller heads for and its proposition values.",
    params=[
        *MAP_PARAMS,
        Param("frame_id", "map", "frame the regions are drawn in", ros_name=True),
        Param("state_topic", "controller_executor/state", "the executor's ~state", ros_name=True),
        Param("region_topic", "localized_region", "the robot's region (std_msgs/String, e.g. from "
              "region_localization); empty: from the controller's R_rc inputs", ros_name=True),
        Param("region_suffix", "_rc", "without a ~region_topic message: the region R whose input R<suffix> is "
              "true (the controller's region sensing)"),
        Param("rate", 2.0, "republish this often (Hz)", bound=Bound.RATE),
        Param("draw_regions", True, "draw the regions (false: only the controller's text, for the other "
              "robots of a scenario whose map one map_markers draws)"),
        Param("label", "", "first line of the controller's text (a robot's name when several run)"),
        Param("text_row", 0, "stack the text this many rows above the map (one row per robot)",
              bound=Bound.NON_NEGATIVE),
    ],
)


#: height (m) of one robot's text block, for ~text_row
TEXT_ROW = 1.0


def _color(rgba: tuple[float, float, float, float]) -> ColorRGBA:
    return ColorRGBA(*rgba)


@dataclass(frozen=True)
class StateView:
    """What map_markers shows of one ControllerState (decoded once, when it arrives)."""

    state_id: int
    goal_index: int
    mode: str
    inputs: dict[str, bool]
    outputs: dict[str, bool]
    running: bool = True


def state_view(msg: Any) -> StateView:
    """ValueError (``MalformedValuation`` among them)/TypeError when the message cannot be read."""
    inputs, outputs = state_valuations(msg)
    return StateView(int(msg.state_id), int(msg.goal_index), str(msg.mode), inputs, outputs, bool(msg.running))


class MarkerBuilder:
    """The marker arrays of one map, without a node: the static one (built once) and the one of a
    state (its work bounded by the highlighted regions and the text)."""

    def __init__(self, regions: RegionMap, config: dict[str, Any]) -> None:
        from visualization_msgs.msg import Marker, MarkerArray

        self.Marker, self.MarkerArray = Marker, MarkerArray
        self.regions, self.config = regions, config
        self.shapes = region_shapes(regions, None, set()) if config["draw_regions"] else []
        self.fills = {shape.key: shape.points for shape in self.shapes if shape.kind == "fill"}
        points = [p for region in regions.regions.values() for p in region.polygon] or [(0.0, 0.0)]
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        self.text_at = ((min(xs) + max(xs)) / 2, max(ys) + 0.45 + TEXT_ROW * config["text_row"])

    def static_array(self, stamp: Any) -> Any:
        """Outline, grey fill and name of every region."""
        array = self.MarkerArray()
        for index, shape in enumerate(self.shapes):
            marker = self._marker(shape.kind, index, stamp)
            marker.color = _color(shape.color)
            if shape.kind == "label":
                marker.type = self.Marker.TEXT_VIEW_FACING
                marker.text = shape.text
                marker.scale.z = 0.22
                marker.pose.position.x, marker.pose.position.y = shape.points[0]
                marker.pose.position.z = 0.1
            else:
                marker.type = self.Marker.LINE_STRIP if shape.kind == "outline" else self.Marker.TRIANGLE_LIST
                marker.scale.x = marker.scale.y = marker.scale.z = 0.04 if shape.kind == "outline" else 1.0
                marker.points = [PointMsg(x=x, y=y, z=0.0 if shape.kind == "fill" else 0.01)
                                 for x, y in shape.points]
            array.markers.append(marker)
        return array

    def state_array(self, view: StateView | None, localized: str | None, stamp: Any) -> Any:
        """DELETEALL, the highlighted regions (``highlight``: green where the robot is, orange where
        it heads), the controller's text (``controller``, last)."""
        inputs = view.inputs if view is not None else {}
        outputs = view.outputs if view is not None else {}
        array = self.MarkerArray()
        if self.config["draw_regions"]:
            clear = self._marker("highlight", 0, stamp)
            clear.action = self.Marker.DELETEALL
            array.markers.append(clear)
            current = localized if localized in self.fills else \
                region_from_inputs(self.regions, inputs, self.config["region_suffix"])
            heading = heading_regions(self.regions, outputs) - {current}
            for name in sorted(heading) + ([current] if current in self.fills else []):
                marker = self._marker("highlight", len(array.markers), stamp)
                marker.type = self.Marker.TRIANGLE_LIST
                marker.color = _color(CURRENT if name == current else HEADING)
                marker.scale.x = marker.scale.y = marker.scale.z = 1.0
                marker.text = name
                marker.points = [PointMsg(x=x, y=y, z=0.005) for x, y in self.fills.get(name, ())]
                array.markers.append(marker)
        text = self._marker("controller", 0, stamp)
        text.type = self.Marker.TEXT_VIEW_FACING
        text.color = _color((0.0, 0.0, 0.3, 1.0))
        text.scale.z = 0.2
        text.pose.position.x, text.pose.position.y = self.text_at
        text.text = (valuation_text(inputs, outputs, view.state_id, view.goal_index, None, view.mode, view.running)
                     if view is not None else "waiting for the controller's state")
        if self.config["label"]:
            text.text = f"{self.config['label']}: {text.text}"
        array.markers.append(text)
        return array

    def _marker(self, ns: str, index: int, stamp: Any) -> Any:
        marker = self.Marker()
        marker.header.frame_id = self.config["frame_id"]
        marker.header.stamp = stamp
        marker.ns, marker.id = ns, index
        marker.action = self.Marker.ADD
        marker.pose.orientation.w = 1.0
        return marker


class MapMarkers:
    def __init__(self, config: dict[str, Any]) -> None:
        from visualization_msgs.msg import MarkerArray

        self.config = config
        has_map = bool(config["regions_file"] or read_param("regions_file", ""))
        regions = load_map(config) if has_map else RegionMap(regions={})
        for warning in regions.warnings:
            rospy.logwarn("%s: %s", rospy.get_name(), warning)
        self.builder = MarkerBuilder(regions, config)
        self.lock = threading.Lock()
        self.localized: str | None = None
        self.state: StateView | None = None
        self._refused: set[str] = set()
        self.pub = rospy.Publisher("markers", MarkerArray, queue_size=1, latch=True)
        if config["draw_regions"]:
            static = rospy.Publisher("region_markers", MarkerArray, queue_size=1, latch=True)
            static.publish(self.builder.static_array(rospy.Time.now()))
        rospy.Subscriber(config["state_topic"], ControllerState, self._on_state, queue_size=10)
        if config["region_topic"]:
            rospy.Subscriber(config["region_topic"], String, self._on_region, queue_size=10)
        self.publish()

    def _on_state(self, msg: Any) -> None:
        if getattr(msg, "settling", False):
            return  # passed through at once: the state reached follows, and only its outputs were published
        try:
            view = state_view(msg)
        except (TypeError, ValueError, OverflowError) as error:
            sender = msg._connection_header.get("callerid", "?") if getattr(msg, "_connection_header", None) \
                else "?"
            if sender not in self._refused:
                self._refused.add(sender)
                rospy.logerr("%s: ignoring a ControllerState from %s that cannot be read: %s", rospy.get_name(),
                             sender, error)
            return
        with self.lock:
            changed = self.state is None or (view.state_id, view.mode, view.running) != (
                self.state.state_id, self.state.mode, self.state.running)
            self.state = view
        if changed:
            self.publish()

    def _on_region(self, msg: Any) -> None:
        with self.lock:
            self.localized = msg.data or None
        self.publish()

    def markers(self) -> Any:
        with self.lock:
            state, localized = self.state, self.localized
        return self.builder.state_array(state, localized, rospy.Time.now())

    def publish(self) -> None:
        self.pub.publish(self.markers())

    def spin(self) -> None:
        rate = rospy.Rate(self.config["rate"])
        while not rospy.is_shutdown():
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
            self.publish()


def map_markers_main() -> None:
    run_node(MAP_MARKERS, MapMarkers)

"""``map_markers``: the region map, the robot's region and the proposition values for RViz.

Publishes a ``visualization_msgs/MarkerArray`` on ``markers`` (latched, on every change and every
1/``~rate`` s): each region of the scenario's ``.regions`` map outlined, filled green where the robot
is (``localized_region``, else the controller's ``R_rc`` inputs), orange where the controller heads
(a true output named as the region), grey elsewhere, with its name (no map: no regions); and a text block with the
controller's state, goal, mode and true propositions (from its ``~state``). The shapes are computed
ROS-free in ``ltl_stack.runtime.map_view``.
"""
from __future__ import annotations

import threading
from typing import Any

import rospy
from geometry_msgs.msg import Point as PointMsg
from std_msgs.msg import ColorRGBA, String

from ltl_stack.msg import ControllerState
from ltl_stack.ros.localization import MAP_PARAMS, load_map
from ltl_stack.ros.proposition_node import NodeSpec, Param, run_node
from ltl_stack.ros.valuation import MalformedValuation, state_valuations
from ltl_stack.runtime.map_view import region_from_inputs, region_shapes, valuation_text
from ltl_stack.runtime.node_params import Bound
from ltl_stack.runtime.regions import RegionMap

MAP_MARKERS = NodeSpec(
    name="map_markers",
    kind="view",
    description="RViz markers (visualization_msgs/MarkerArray on markers): the region map, the robot's "
                "region, the regions the controller heads for and its proposition values.",
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


class MapMarkers:
    def __init__(self, config: dict[str, Any]) -> None:
        from visualization_msgs.msg import Marker, MarkerArray

        self.Marker, self.MarkerArray = Marker, MarkerArray
        self.config = config
        has_map = bool(config["regions_file"] or rospy.get_param("regions_file", ""))
        self.regions = load_map(config) if has_map else RegionMap(regions={})
        self.lock = threading.Lock()
        self.localized: str | None = None
        self.state: Any = None
        self.pub = rospy.Publisher("markers", MarkerArray, queue_size=1, latch=True)
        rospy.Subscriber(config["state_topic"], ControllerState, self._on_state, queue_size=10)
        if config["region_topic"]:
            rospy.Subscriber(config["region_topic"], String, self._on_region, queue_size=10)
        self.publish()

    def _on_state(self, msg: Any) -> None:
        with self.lock:
            changed = self.state is None or (msg.state_id, msg.mode) != (self.state.state_id, self.state.mode)
            self.state = msg
        if changed:
            self.publish()

    def _on_region(self, msg: Any) -> None:
        with self.lock:
            self.localized = msg.data or None
        self.publish()

    def markers(self) -> Any:
        with self.lock:
            state, localized = self.state, self.localized
        inputs, outputs = {}, {}
        if state is not None:
            try:
                inputs, outputs = state_valuations(state)
            except MalformedValuation as err:  # drawn as if no state had come
                rospy.logwarn_throttle(60, "%s: %s: skipping a state message that cannot be read: %s",
                                       rospy.get_name(), self.config["state_topic"], err)
        current = localized or region_from_inputs(self.regions, inputs, self.config["region_suffix"])
        heading = {name for name in self.regions.names() if outputs.get(name)}
        array = self.MarkerArray()
        stamp = rospy.Time.now()
        shapes = region_shapes(self.regions, current, heading) if self.config["draw_regions"] else []
        for index, shape in enumerate(shapes):
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
        text = self._marker("controller", 0, stamp)
        text.type = self.Marker.TEXT_VIEW_FACING
        text.color = _color((0.0, 0.0, 0.3, 1.0))
        text.scale.z = 0.2
        points = [p for region in self.regions.regions.values() for p in region.polygon] or [(0.0, 0.0)]
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        text.pose.position.x = (min(xs) + max(xs)) / 2
        text.pose.position.y = max(ys) + 0.45 + TEXT_ROW * self.config["text_row"]
        text.text = (valuation_text(inputs, outputs, state.state_id, state.goal_index, None, state.mode)
                     if state is not None else "waiting for the controller's state")
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

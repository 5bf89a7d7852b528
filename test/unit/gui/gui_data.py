"""Test data of the GUI tests: the project's scenarios and the analysis scenario graphs as snapshots."""
from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
CONFIG = ROOT / "config"
ANALYSIS_DATA = ROOT / "test" / "data" / "analysis"
CLEAN = CONFIG / "clean_and_patrol"
CLEAN_SPEC = CLEAN / "clean_and_patrol.structuredslugs"
CLEAN_MAPPING = CLEAN / "clean_and_patrol.yaml"
SIMPLE_SPEC = CONFIG / "simple" / "simple.structuredslugs"
SIMPLE_MAPPING = CONFIG / "simple" / "simple.yaml"


def _scenario_module():
    spec = importlib.util.spec_from_file_location("gui_scenario_graph", ANALYSIS_DATA / "scenario_graph.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


scenarios = _scenario_module()


def simple_snapshot():
    """The graph of thesis Example 7 as launch/simple.launch runs it: move and stop both on /simple/cmd_vel."""
    from ltl_stack.analysis.snapshot import Snapshot

    pubs = [("/simple/inputs/person", ["/simple/person"]), ("/simple/cmd_vel", ["/simple/move", "/simple/stop"]),
            ("/simple/camera/person_distance", ["/simple/camera"]),
            ("/rosout", ["/simple/move", "/simple/stop", "/simple/sim_robot"])]
    subs = [("/simple/outputs/move", ["/simple/move"]), ("/simple/outputs/stop", ["/simple/stop"]),
            ("/simple/cmd_vel", ["/simple/sim_robot"]), ("/simple/camera/person_distance", ["/simple/person"])]
    types = [("/simple/inputs/person", "std_msgs/Bool"), ("/simple/outputs/move", "std_msgs/Bool"),
             ("/simple/outputs/stop", "std_msgs/Bool"), ("/simple/cmd_vel", "geometry_msgs/Twist"),
             ("/simple/camera/person_distance", "std_msgs/Float64")]
    return Snapshot.from_system_state(pubs, subs, [], types, master="test")

"""A node started by roslaunch without one of requirements.txt's packages says which, and how to install
it, in one line (exit 2) that roslaunch shows: no traceback (``ltl_stack.missing``).

A ROS user who built the package in their own workspace but skipped ``pip install -r requirements.txt``
meets this first under roslaunch. Each case hides one package from one node: the launch file gives
the node a ``PYTHONPATH`` (roslaunch's ``<env>``) that starts with a folder where that package's
import fails as an absent package's does; roslaunch itself (which imports PyYAML) keeps the real one.
The node is ``required``, as the executor is in our launch files: its exit ends the launch.
"""
from __future__ import annotations

import pytest
from helpers import REPO_ROOT, wait_for

pytestmark = pytest.mark.ros

SIMPLE = REPO_ROOT / "config" / "simple"
LAUNCH = """<launch>
  <node name="{node}" pkg="ltl_stack" type="{node}" required="true" {output} args="{args}">
    <env name="PYTHONPATH" value="{hidden}:$(env PYTHONPATH)"/>
  </node>
</launch>
"""


@pytest.mark.parametrize(("node", "module", "package", "output", "args"), [
    # the executor prints to the screen in our launch files; yaml: its mapping reader, and rospy's
    ("controller_executor", "yaml", "PyYAML", 'output="screen"',
     f"{SIMPLE / 'simple.structuredslugs'} {SIMPLE / 'simple.yaml'}"),
    # a proposition node with roslaunch's default output (its stderr still reaches the screen)
    ("region_localization", "shapely", "shapely", "", ""),
])
def test_a_node_without_a_package_says_which_in_one_line_under_roslaunch(ros_master, tmp_path, node, module,
                                                                       package, output, args):
    hidden = tmp_path / "hidden"
    hidden.mkdir()
    (hidden / f"{module}.py").write_text(f"raise ModuleNotFoundError({f'No module named {module!r}'!r}, "
                                         f"name={module!r})\n")
    launch = tmp_path / f"{node}.launch"
    launch.write_text(LAUNCH.format(node=node, output=output, args=args, hidden=hidden))
    roslaunch = ros_master.run(["roslaunch", str(launch)], name="roslaunch")
    # the required node's death ends roslaunch
    wait_for(lambda: not roslaunch.running(), 120, "roslaunch to end after its required node exited")
    out = roslaunch.output()
    errors = [line for line in out.splitlines() if "error:" in line]
    assert len(errors) == 1, out[-4000:]
    assert errors[0].startswith(f"{node}: error: the Python package '{package}' is missing; "), errors
    assert "pip install -r" in errors[0] and "requirements.txt" in errors[0], errors
    assert "exit code 2" in out, out[-4000:]
    assert "Traceback" not in out, out[-4000:]
    # the node's own log holds no traceback either (rospy writes one there for an error it catches)
    logs = list((tmp_path / "log").rglob(f"*{node}*.log"))
    assert all("Traceback" not in log.read_text(errors="replace") for log in logs), logs

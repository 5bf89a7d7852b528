"""Small simulated robots and action servers so every example runs without a robot.

The simulated nodes import ``rospy`` before anything of ``ltl_stack.ros``; importing that package
here first keeps genpy's optional numpy import out of them too (see ``ltl_stack/ros/__init__.py``:
~0.2 s CPU per simulated node, and a scenario starts dozens).
"""
import ltl_stack.ros  # noqa: F401 - for the start-up reason above

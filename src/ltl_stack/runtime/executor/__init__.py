"""The controller executor's core, ROS-free: stepping, the node's modes, options and setup."""

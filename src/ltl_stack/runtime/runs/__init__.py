"""A run of the controller, ROS-free: readable traces, conformance, what RViz shows."""

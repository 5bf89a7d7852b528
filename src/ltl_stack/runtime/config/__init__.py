"""The mapping format and the ROS conventions, ROS-free: the proposition mapping YAML, node parameters, ROS names, launch files."""

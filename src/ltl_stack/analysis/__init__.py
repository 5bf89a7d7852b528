"""ROS computation-graph model and conflict checks (thesis section 3.5.2); ROS-free."""

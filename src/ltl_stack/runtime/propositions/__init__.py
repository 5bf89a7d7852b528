"""The cores of the proposition nodes, ROS-free: edges, sensing, predicates, regions and localization."""

"""ROS-free execution: stepping strategies, assumption monitoring, characterization, negotiation."""

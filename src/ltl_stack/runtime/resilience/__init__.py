"""Resilient execution (thesis ch. 4), ROS-free: characterization, resynthesis, stories, negotiation."""

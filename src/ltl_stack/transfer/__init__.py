"""Automatic ROS code transfer between robots (thesis chapter 2); ROS-free core."""

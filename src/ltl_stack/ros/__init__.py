"""ROS adapters: executor node, proposition nodes, graph snapshots, transports."""

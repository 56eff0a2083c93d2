"""ROS nodes of blind_navigation: one module per node, each runnable as a script."""

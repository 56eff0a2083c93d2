"""ROS-free core of blind_navigation (no rospy), run alike by the nodes and the harness."""

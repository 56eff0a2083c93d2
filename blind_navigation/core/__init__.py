"""ROS-free core of blind_navigation; nothing here imports rospy.

The same code runs inside the ROS nodes and inside the plain-Python simulation
harness used for Monte-Carlo evaluation.
"""

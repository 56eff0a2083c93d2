"""RTAB-Map's OdomInfo for the fake TurtleBot and the tests, without rtabmap packages.

``OdomInfo`` is generated at import (genpy.dynamic) as ``rtabmap_msgs/OdomInfo``
with the message's leading fields: ``header``, ``lost``, ``matches``,
``inliers``. The layer reads only the ``lost`` flag right after the header
(core/vision.odom_info_lost) and checks the type name, not the MD5 sum (it
changes between rtabmap releases: ros/vision_monitor.ODOM_INFO).
"""
import genpy.dynamic

DEFINITION = """std_msgs/Header header
bool lost
int32 matches
int32 inliers
================================================================================
MSG: std_msgs/Header
uint32 seq
time stamp
string frame_id
"""
OdomInfo = genpy.dynamic.generate_dynamic('rtabmap_msgs/OdomInfo', DEFINITION)['rtabmap_msgs/OdomInfo']

"""Small rospy glue shared by every node: watched subscriptions, Twist, poses, ROS_HOME."""
import os

import rospkg
import rospy
from geometry_msgs.msg import Twist, Vector3

from . import faults, subscription_watchdog
from .faults import shutting_down  # noqa: F401 -- the roles' one import of it
from ..core.geometry import quaternion_from_yaw


def subscribe(topic, data_class, callback, callback_args=None, expected=None, **options):
    """``rospy.Subscriber`` checked by the subscription watchdog (its type too, with ``expected``)."""
    return subscription_watchdog.watch(rospy.Subscriber(topic, data_class, callback, callback_args,
                                                        **options), expected)


def subscribe_checked(topic, data_class, callback, callback_args=None, **options):
    """:func:`subscribe` of ``topic`` as ``data_class``, another type refused."""
    expected = faults.Expected.of(data_class)

    def on_raw(raw, args=None):
        if expected.accepts(topic, raw._connection_header):
            msg = data_class()
            msg.deserialize(raw._buff)
            callback(msg) if callback_args is None else callback(msg, args)
    return subscribe(topic, rospy.AnyMsg, on_raw, callback_args, expected, **options)


def twist(v=0.0, w=0.0):
    """geometry_msgs/Twist with linear.x = v and angular.z = w."""
    return Twist(linear=Vector3(x=v), angular=Vector3(z=w))


def ros_home_file(relative, configured=''):
    """The file ``configured`` (a path param), or if empty ``relative`` under $ROS_HOME."""
    return os.path.abspath(os.path.expanduser(configured.strip() or os.path.join(
        rospkg.get_ros_home(), relative)))


def set_pose(pose_msg, x, y, yaw):
    """Fill a geometry_msgs/Pose in place from a planar pose (x, y in m, yaw in rad)."""
    pose_msg.position.x, pose_msg.position.y = x, y
    q = pose_msg.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(yaw)

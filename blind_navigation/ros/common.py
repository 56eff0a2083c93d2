"""Small rospy glue shared by every node (the layer's and the fake TurtleBot's):
params, watched (and type-checked) subscriptions, message conversions, Twist, a
wall-bounded wait."""
import math
import os
import time

import rospkg
import rospy
from geometry_msgs.msg import Twist

from . import subscription_watchdog, wiring
from .faults import shutting_down  # noqa: F401 -- the roles' one import of it
from ..core.geometry import OdomState, quaternion_from_yaw, yaw_from_quaternion
from ..core.params import REQUIRED



def wait_wall(condition, timeout, poll=0.05):
    """Poll ``condition()`` every ``poll`` s until it is true, ``timeout`` s (wall) passed
    or the node shuts down; returns its last value."""
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline and not rospy.is_shutdown():
        time.sleep(poll)
    return condition()


def load_params(defaults, namespace='~'):
    """Read each param ``namespace + name`` (private ``~name`` by default, ``~role/name``
    for a role hosted with others in one process), falling back to ``defaults[name]``;
    a :data:`REQUIRED` param that is not set is a ValueError naming it.

    Returns a plain object with one attribute per param and logs the values, so
    every node documents and reads its params the same way.
    """
    values = {name: rospy.get_param(namespace + name, default) for name, default in defaults.items()}
    missing = sorted(name for name, value in values.items() if value is REQUIRED)
    if missing:
        raise ValueError('%s not set (the launch files set %s; with rosrun give _%s:=...)'
                         % (', '.join(namespace + name for name in missing),
                            'them' if len(missing) > 1 else 'it', missing[0]))
    rospy.loginfo('%s params%s: %s', rospy.get_name(), '' if namespace == '~' else ' ' + namespace,
                  ', '.join('%s=%r' % item for item in sorted(values.items())))
    return type('Params', (object,), values)()


def subscribe(topic, data_class, callback, callback_args=None, expected=None, **options):
    """``rospy.Subscriber`` whose registration the subscription watchdog checks
    (a publisher registering at the same moment is not missed); with ``expected``
    (ros/wiring.Expected: for a raw ``rospy.AnyMsg`` subscription) the watchdog
    also checks the topic's type at the master."""
    return subscription_watchdog.watch(rospy.Subscriber(topic, data_class, callback, callback_args,
                                                        **options), expected)


def subscribe_checked(topic, data_class, callback, callback_args=None, **options):
    """:func:`subscribe` of ``topic`` as ``data_class`` that refuses another type
    (ros/wiring.py): raw bytes, checked per connection, then deserialised."""
    expected = wiring.Expected.of(data_class)

    def on_raw(raw, args=None):
        if expected.accepts(topic, raw._connection_header):
            msg = data_class()
            msg.deserialize(raw._buff)
            callback(msg) if callback_args is None else callback(msg, args)
    return subscribe(topic, rospy.AnyMsg, on_raw, callback_args, expected, **options)


def odom_state_from_msg(msg):
    """OdomState from nav_msgs/Odometry; ValueError if the pose is NaN or the quaternion null."""
    pose, twist = msg.pose.pose, msg.twist.twist
    q = pose.orientation
    yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w)
    values = (pose.position.x, pose.position.y, twist.linear.x, twist.angular.z)
    if not all(math.isfinite(v) for v in values):
        raise ValueError('non-finite odometry (x, y, v, w) = %r' % (values,))
    return OdomState(pose.position.x, pose.position.y, yaw, twist.linear.x,
                     twist.angular.z, msg.header.stamp.to_sec())


def twist(v=0.0, w=0.0):
    """geometry_msgs/Twist with linear.x = v and angular.z = w."""
    msg = Twist()
    msg.linear.x = v
    msg.angular.z = w
    return msg


def start_node(name, node_class, *args):
    """``rospy.init_node(name)`` then ``node_class(*args)``; a ValueError from the
    constructor (a bad param) is logged as fatal and exits with status 1."""
    rospy.init_node(name)
    try:
        return node_class(*args)
    except ValueError as error:
        rospy.logfatal('%s: %s', rospy.get_name(), error)
        raise SystemExit(1)


def ros_home_file(relative):
    """``relative`` under $ROS_HOME (default ~/.ros), where ROS keeps a user's files."""
    return os.path.join(rospkg.get_ros_home(), relative)


def set_pose(pose_msg, x, y, yaw):
    """Fill a geometry_msgs/Pose in place from a planar pose (x, y in m, yaw in rad)."""
    pose_msg.position.x, pose_msg.position.y = x, y
    q = pose_msg.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(yaw)

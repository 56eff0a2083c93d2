"""Storage of a recorded path: the landmark file vs a rosbag of /odom.

:func:`write_odom_bag` writes a real rosbag (rosbag Python API, uncompressed as
``rosbag record`` by default) of the forward run's wheel odometry at the
harness's 50 Hz, as nav_msgs/Odometry messages filled like the fake Kobuki's
(same frames and kobuki_node covariances), so the bag is what
``rosbag record /odom`` would have stored for the same mission.
"""
import os

import rosbag
import rospy
from nav_msgs.msg import Odometry

from ..ros.common import set_pose
from ..sim.kobuki import ODOM_POSE_COVARIANCE


def odom_message(state, stamp, frame='odom', child_frame='base_footprint'):
    """nav_msgs/Odometry for an OdomState at ``stamp`` (s)."""
    msg = Odometry()
    msg.header.stamp = rospy.Time.from_sec(stamp)
    msg.header.frame_id, msg.child_frame_id = frame, child_frame
    for index, value in ODOM_POSE_COVARIANCE.items():
        msg.pose.covariance[index] = value
    set_pose(msg.pose.pose, state.x, state.y, state.yaw)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = state.v, state.w
    return msg


def write_odom_bag(path, forward, topic='/odom'):
    """Bag of ``forward``'s odometry (a ForwardRecord); returns the file size, bytes."""
    with rosbag.Bag(path, 'w') as bag:
        for seq, (state, (t, _)) in enumerate(zip(forward.odometry, forward.truth)):
            msg = odom_message(state, t)
            msg.header.seq = seq
            bag.write(topic, msg, msg.header.stamp)
    return os.path.getsize(path)

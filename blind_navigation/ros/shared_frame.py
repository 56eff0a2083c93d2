"""An odometry reset's frame shared between the feeds of a robot's processes.

When one process's feed carries a reset across in the old frame
(core/odometry_reset.ResetCarrier), :class:`SharedFrame` publishes that frame,
latched, and every other process's feed adopts it instead of estimating its own:
all of them stay in one frame. Why: docs/safety.md, "Odometry resets".
"""
import rospy
from geometry_msgs.msg import PoseStamped

from ..core.geometry import yaw_from_quaternion
from ..core.odometry_reset import Frame
from .common import set_pose, subscribe


class SharedFrame(object):
    """The reset frames of ``feed`` (ros/odometry.OdometryFeed) on ``topic``."""

    def __init__(self, feed, topic, guard=None):
        self.feed = feed
        self._pub = rospy.Publisher(topic, PoseStamped, queue_size=1, latch=True)
        subscribe(topic, PoseStamped, guard(self._on_frame) if guard else self._on_frame)

    def publish(self):
        """Share the frame the feed's carrier carried its last reset across with."""
        carrier = self.feed.carrier
        msg = PoseStamped()
        msg.header.stamp = rospy.Time.from_sec(carrier.reset_stamp)
        msg.header.frame_id = self.feed.frame_id
        set_pose(msg.pose, *carrier.frame)
        self._pub.publish(msg)

    def _on_frame(self, msg):
        """Another node's feed carried a reset across: take its frame unless this one did."""
        q = msg.pose.orientation
        frame = Frame(msg.pose.position.x, msg.pose.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
        feed = self.feed
        with feed.carrier_lock:
            taken = feed.carrier.adopt(frame, msg.header.stamp.to_sec())
            if taken == 'restart':
                feed.clear_history()    # taken in the odometry's new frame as it came
        if taken:
            rospy.logwarn('%s: odometry on %s: the frame %s carried a reset at %.3f s across with: '
                          '(%.3f, %.3f, %.3f)', rospy.get_name(), rospy.resolve_name(feed.topic),
                          msg._connection_header.get('callerid', '?'), msg.header.stamp.to_sec(),
                          *frame)

"""rospy glue shared by the back-travel nodes (rotate_pi, back_travel_server,
back_travel_client): topic names, the latest-odometry holder with a staleness
check, and a clamped velocity output that stops the robot on shutdown."""
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from blind_navigation.ros_common import odom_state_from_msg, twist

VISION_LOST_TOPIC = '/blind_navigation/vision_lost'
ROTATION_DONE_TOPIC = '/blind_navigation/rotation_done'
STATE_TOPIC = '/blind_navigation/state'
FOOTPRINT_TOPIC = '/blind_navigation/footprint'
RETURN_PATH_TOPIC = '/blind_navigation/return_path'
BACK_TRAVEL_ACTION = '/blind_navigation/back_travel'


class LatestOdom(object):
    """Keeps the newest valid odometry of ``topic``; ``fresh(timeout)`` returns it
    (as OdomState, stamp = now) or None when none arrived within ``timeout`` s.
    ``on_state(state, msg)``, if given, is called for each valid message."""

    def __init__(self, topic, on_state=None):
        self.topic = topic
        self.frame_id = 'odom'
        self._lock = threading.Lock()
        self._state = None
        self._received = None
        self._on_state = on_state
        self._sub = rospy.Subscriber(topic, Odometry, self._on_msg, queue_size=5)

    def _on_msg(self, msg):
        try:
            state = odom_state_from_msg(msg)
        except ValueError as error:
            rospy.logwarn_throttle(5.0, '%s: odometry on %s ignored: %s'
                                   % (rospy.get_name(), self.topic, error))
            return
        with self._lock:
            self._state, self._received = state, rospy.Time.now()
            self.frame_id = msg.header.frame_id or self.frame_id
        if self._on_state:
            self._on_state(state, msg)

    def fresh(self, timeout):
        now = rospy.Time.now()
        with self._lock:
            if self._state is None or (now - self._received).to_sec() > timeout:
                return None
            return self._state._replace(stamp=now.to_sec())

    def describe_missing(self, timeout):
        """Why :meth:`fresh` returned None, for logs and action results."""
        if self._received is None:
            return 'no valid odometry received on %s' % self.topic
        return 'odometry on %s is older than %.2f s' % (self.topic, timeout)


class VelocityOutput(object):
    """Publishes geometry_msgs/Twist on ``topic`` clamped to ``max_v``/``max_w``;
    publishes zero on :meth:`stop` and on node shutdown."""

    def __init__(self, topic, max_v, max_w):
        if max_v < 0 or max_w <= 0:
            raise ValueError('velocity limits: need max_v >= 0 and max_w > 0 (max_v %r, max_w %r)'
                             % (max_v, max_w))
        self.topic = topic
        self.max_v, self.max_w = float(max_v), float(max_w)
        self._pub = rospy.Publisher(topic, Twist, queue_size=1)
        rospy.on_shutdown(self.stop)

    def publish(self, v, w):
        v = max(-self.max_v, min(self.max_v, v))
        w = max(-self.max_w, min(self.max_w, w))
        self._pub.publish(twist(v, w))

    def stop(self):
        try:
            self._pub.publish(twist(0.0, 0.0))
        except rospy.ROSException:
            pass  # publisher already closed at shutdown

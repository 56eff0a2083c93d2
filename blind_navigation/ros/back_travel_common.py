"""rospy glue shared by the back-travel nodes (rotate_pi, back_travel_server,
back_travel_client, calibrate_gyro): the latest-odometry holder with a staleness
check, a clamped velocity output that can be halted and stops the robot on
shutdown, and the Kobuki safety-event watcher (core/safety.py rules)."""
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from blind_navigation.ros import kobuki_msgs_compat as kobuki
from blind_navigation.core.heading_correction import GyroCorrection, correct_landmarks
from blind_navigation.core.safety import SafetyEvents, VelocityLimits
from blind_navigation.ros.common import twist, usable_odom_state

EVENT_TYPES = {'bumper': (kobuki.BumperEvent, 'bumper'), 'cliff': (kobuki.CliffEvent, 'sensor'),
               'wheel_drop': (kobuki.WheelDropEvent, 'wheel')}


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
        self._sub = rospy.Subscriber(topic, Odometry, self._on_msg, queue_size=5, tcp_nodelay=True)

    def _on_msg(self, msg):
        state = usable_odom_state(msg, self.topic)
        if state is None:
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


class SafetyMonitor(object):
    """Watches Kobuki's bumper, cliff and wheel-drop events (``topics``: kind ->
    topic); ``on_trip(reason)`` is called from the subscriber thread when a
    sensor becomes active. ``active`` lists the conditions active now."""

    def __init__(self, topics, on_trip=None):
        self._events = SafetyEvents()
        self._lock = threading.Lock()
        self._on_trip = on_trip
        self.last_reason = None
        for kind, topic in topics.items():
            msg_type, index_field = EVENT_TYPES[kind]
            rospy.Subscriber(topic, msg_type, self._on_event, (kind, index_field), queue_size=10)

    def _on_event(self, msg, args):
        kind, index_field = args
        with self._lock:
            reason = self._events.update(kind, getattr(msg, index_field), msg.state)
            if reason:
                self.last_reason = reason
        if reason:
            rospy.logerr('%s: SAFETY STOP: %s', rospy.get_name(), reason)
            if self._on_trip:
                self._on_trip(reason)

    @property
    def active(self):
        with self._lock:
            return self._events.active


class VelocityOutput(object):
    """Publishes geometry_msgs/Twist on ``topic`` within ``max_v``/``max_w`` and
    the current goal's :meth:`limit` (core/safety.VelocityLimits.clamp: v and w
    scaled together); publishes zero on :meth:`stop` and on node shutdown.
    :meth:`halt` stops at once and turns every later :meth:`publish` into zero
    until :meth:`release`, so a control loop that computed its command before a
    cancel or a safety event cannot move the robot again."""

    def __init__(self, topic, max_v, max_w):
        if max_v < 0 or max_w <= 0:
            raise ValueError('velocity limits: need max_v >= 0 and max_w > 0 (max_v %r, max_w %r)'
                             % (max_v, max_w))
        self.topic = topic
        self.max_v, self.max_w = float(max_v), float(max_w)
        self.limits = VelocityLimits(self.max_v, self.max_w)
        self.halted = None          # why, while halted
        self._lock = threading.Lock()
        self._pub = rospy.Publisher(topic, Twist, queue_size=1)
        rospy.on_shutdown(lambda: self.halt('node shutdown'))

    def limit(self, limits=None):
        """Clamp to ``limits`` (a goal's) as well as the configured ones; None resets."""
        with self._lock:
            self.limits = VelocityLimits(min(self.max_v, limits.max_v), min(self.max_w, limits.max_w)) \
                if limits else VelocityLimits(self.max_v, self.max_w)

    def publish(self, v, w):
        with self._lock:
            v, w = self.limits.clamp(v, w) if self.halted is None else (0.0, 0.0)
            self._send(v, w)

    def stop(self):
        with self._lock:
            self._send(0.0, 0.0)

    def halt(self, reason):
        with self._lock:
            self.halted = reason
            self._send(0.0, 0.0)

    def release(self):
        with self._lock:
            self.halted = None

    def _send(self, v, w):
        try:
            self._pub.publish(twist(v, w))
        except rospy.ROSException:
            pass  # publisher already closed at shutdown


def landmarks_in_corrected_frame(landmarks, msg):
    """``landmarks`` expressed in the corrected odometry frame of ``msg`` (a
    blind_navigation/HeadingCorrection from the heading_correction node), as
    back_travel_client sends them; also the correction (core HeadingCorrection)."""
    correction = GyroCorrection(msg.bias, msg.scale, msg.bias_std, msg.scale_std,
                                   msg.windows, msg.status, msg.reason)
    return correct_landmarks(landmarks, correction, msg.reference_yaw), correction

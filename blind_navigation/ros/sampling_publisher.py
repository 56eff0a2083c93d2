"""sampling_publisher: the paper's publisher of sampling ticks (sections 3.3.2, 3.4.1).

Reads the yaw from odometry (nav_msgs/Odometry on ``odom_topic``, or a
geometry_msgs/Pose2D topic as the paper did) and runs a ``rospy.Rate`` loop
whose rate switches between the straight-segment and the curved-segment rate
(paper: 0.5 Hz / 1 Hz) by the paper's classifier over the last four yaws
(core/segment.SamplingSchedule); a switch takes effect at the next cycle.
Each cycle it publishes blind_navigation/PathSample (command ``sample``, the
yaw, the period of the cycle that just ended) on /blind_navigation/sample.

Recording starts with the first valid yaw (launch this node last, section
3.4.2). On /blind_navigation/vision_lost, or when /blind_navigation/state says
the mission left recording (rotating, returning, home, aborted), it publishes
one last sample with command ``final`` covering the partial cycle since the
last tick (period = elapsed time) and stops. It does not start while the
state is one of those.
"""
import math
import threading

import rospy
from geometry_msgs.msg import Pose2D
from nav_msgs.msg import Odometry
from std_msgs.msg import Empty, String

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.segment import SamplingSchedule
from blind_navigation.msg import PathSample
from blind_navigation.ros.landmark_saving import FINAL, SAMPLE
from blind_navigation.ros.common import load_params, odom_state_from_msg

#: States in which the path is not recorded.
NOT_RECORDING = (mission_state.ROTATING, mission_state.RETURNING, mission_state.HOME,
                 mission_state.ABORTED)
#: Shortest partial cycle worth a final landmark, s.
MIN_FINAL_PERIOD = 1e-3


class SamplingPublisher(object):
    """Two-rate sampling publisher.

    Params (DEFAULTS): ``odom_topic`` (nav_msgs/Odometry, '/odom'),
    ``pose2d_topic`` (if set, the yaw comes from geometry_msgs/Pose2D on this
    topic instead, ''), ``straight_rate`` (Hz, 0.5), ``curved_rate`` (Hz, 1.0),
    ``deadband`` (rad per yaw difference, see core/segment.py, 0.01),
    ``min_subscribers`` (recording starts once this many nodes subscribe to the
    samples: the saver, or the record client, is up, 1).
    """

    DEFAULTS = {
        'odom_topic': '/odom',
        'pose2d_topic': '',
        'straight_rate': 0.5,
        'curved_rate': 1.0,
        'deadband': 0.01,
        'min_subscribers': 1,
    }

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        for name in ('straight_rate', 'curved_rate'):
            rate = getattr(p, name)
            if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not rate > 0:
                raise ValueError('~%s must be a positive number of Hz, got %r' % (name, rate))
        self.schedule = SamplingSchedule(1.0 / p.straight_rate, 1.0 / p.curved_rate, p.deadband)
        self._lock = threading.Lock()
        self._yaw = None
        self._state = None
        self._last_tick = None      # rospy.Time of the last tick (or of the start)
        self.stopped = False
        self.sample_pub = rospy.Publisher(names.SAMPLE, PathSample, queue_size=10)
        if p.pose2d_topic:
            self.source = p.pose2d_topic
            rospy.Subscriber(p.pose2d_topic, Pose2D, self._on_pose2d, queue_size=10)
        else:
            self.source = p.odom_topic
            rospy.Subscriber(p.odom_topic, Odometry, self._on_odom, queue_size=10)
        rospy.Subscriber(names.VISION_LOST, Empty, self._on_vision_lost, queue_size=1)
        rospy.Subscriber(names.STATE, String, self._on_state, queue_size=10)

    # -- inputs -------------------------------------------------------------
    def _on_odom(self, msg):
        try:
            self._set_yaw(odom_state_from_msg(msg).yaw)
        except ValueError as error:
            self._bad_input(error)

    def _on_pose2d(self, msg):
        if math.isfinite(msg.theta):
            self._set_yaw(msg.theta)
        else:
            self._bad_input('theta is %r' % msg.theta)

    def _set_yaw(self, yaw):
        with self._lock:
            self._yaw = yaw

    def _bad_input(self, reason):
        rospy.logwarn_throttle(5.0, '%s: yaw from %s not used: %s'
                               % (rospy.get_name(), self.source, reason))

    def _on_vision_lost(self, _msg):
        self.stop('vision lost')

    def _on_state(self, msg):
        with self._lock:
            self._state = msg.data
        if msg.data in NOT_RECORDING:
            self.stop('mission state is %s' % msg.data)

    # -- the sampling loop ----------------------------------------------------
    def stop(self, reason):
        """Publish the final partial-cycle sample (if recording) and stop for good."""
        with self._lock:
            if self.stopped:
                return
            self.stopped = True
            if self._last_tick is None:
                rospy.loginfo('%s: %s before recording started; nothing recorded',
                              rospy.get_name(), reason)
                return
            elapsed = (rospy.Time.now() - self._last_tick).to_sec()
            if elapsed >= MIN_FINAL_PERIOD:
                self._publish(FINAL, self._yaw, elapsed)
            rospy.loginfo('%s: %s: recording stopped (final partial cycle %.3f s)',
                          rospy.get_name(), reason, elapsed)

    def _publish(self, command, yaw, period):
        """Publish one sample (lock held) and mark the tick."""
        now = rospy.Time.now()
        msg = PathSample(command=command, yaw=yaw, period=period)
        msg.header.stamp = now
        self.sample_pub.publish(msg)
        self._last_tick = now

    def _wait_for_start(self):
        """Until a valid yaw arrives and the state allows recording; False if stopped."""
        logged = False
        while not rospy.is_shutdown():
            with self._lock:
                if self.stopped:
                    return False
                ready = self.sample_pub.get_num_connections() >= self.params.min_subscribers
                if ready and self._yaw is not None and self._state not in NOT_RECORDING:
                    self._last_tick = rospy.Time.now()
                    self.schedule.update(self._yaw)
                    return True
            if not logged:
                rospy.loginfo('%s: waiting for a valid yaw on %s and %d subscriber(s) of %s',
                              rospy.get_name(), self.source, self.params.min_subscribers, names.SAMPLE)
                logged = True
            rospy.sleep(0.05)
        return False

    def run(self):
        if not self._wait_for_start():
            return
        period = self.schedule.period
        rospy.loginfo('%s: recording started; %s segment, period %.3g s', rospy.get_name(),
                      self.schedule.segment, period)
        rate = rospy.Rate(1.0 / period)
        while not rospy.is_shutdown():
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                return
            with self._lock:
                if self.stopped:
                    return
                yaw = self._yaw
                self._publish(SAMPLE, yaw, period)
                next_period = self.schedule.update(yaw)
            if next_period != period:
                rospy.loginfo('%s: %s segment: period %.3g s -> %.3g s', rospy.get_name(),
                              self.schedule.segment, period, next_period)
                rate = self._switch(rate, next_period)
                period = next_period

    @staticmethod
    def _switch(rate, period):
        """A Rate of the new period that keeps the old one's tick phase, so the
        next cycle lasts exactly ``period`` from this tick."""
        switched = rospy.Rate(1.0 / period)
        switched.last_time = rate.last_time
        return switched

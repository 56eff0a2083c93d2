"""heading_correction: calibrates the gyro against visual odometry while vision
works, measures its bias standing still after vision loss, and republishes
odometry in the corrected frame for the return.

While recording, feeds the raw odometry yaw (``odom_topic``) and RTAB-Map's
visual-odometry yaw (``vo_odom_topic``; a lost message, RTAB-Map's convention,
breaks the current window) to core/gyro_fit.GyroVisualFit, and
republishes each odometry message unchanged on ``corrected_odom_topic``.

On /blind_navigation/vision_lost it keeps the last raw odometry as the
reference (where the return starts) and measures the gyro bias with the robot
standing still (core/gyro_bias.StandstillBias on the raw odometry,
stamps from the messages, so sim time works) until
core/gyro_bias.standstill_complete: the bias is known well enough for
this mission (its std x the recording's duration within ``heading_budget``,
after at least ``standstill_min`` s of still odometry), or ``standstill_time``
s of still odometry were counted, or ``standstill_timeout`` s after the
reference passed (the robot kept moving: whatever was counted is used). rotate_pi waits for the
result before it turns (its ``wait_for_heading_correction``). Odometry is still
relayed unchanged meanwhile. Then it estimates the gyro bias (visual odometry
and standstill fused) and scale (from ``gyro_calibration_file`` when there is
one, else not corrected), publishes the result latched on
/blind_navigation/heading_correction (blind_navigation/HeadingCorrection:
reference stamp and raw yaw, bias, scale, standard errors, status, reason),
and from then on republishes odometry through
core/heading_correction.CorrectedOdometry, whose frame equals the raw one at
the reference. rotate_pi, back_travel_server and back_travel_client drive on
``corrected_odom_topic``; back_travel_client expresses the recorded landmarks
in the same frame (core/heading_correction.correct_landmarks).
``standstill_time`` 0: the estimate is made at vision loss, without a
standstill. One estimate per run: a later vision_lost is ignored.
"""
import os
import threading

import rospy
from nav_msgs.msg import Odometry
from std_msgs.msg import Empty

from blind_navigation import names
from blind_navigation.core.gyro_calibration import CalibrationError, load_calibration
from blind_navigation.core.gyro_bias import (STANDSTILL_DEFAULTS, StandstillBias,
                                              standstill_complete, standstill_timeout)
from blind_navigation.core.gyro_fit import GYRO_FIT_DEFAULTS, GyroVisualFit
from blind_navigation.core.heading_correction import (CORRECTION_DEFAULTS, CorrectedOdometry,
                                                       estimate_correction, visual_bias)
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros.common import (load_params, odom_state_from_msg, odometry_lost_reason,
                                         set_pose, usable_odom_state)

#: How to make the gyro calibration file (the warning when it is missing says so).
CALIBRATE_COMMAND = 'roslaunch blind_navigation calibrate_gyro.launch'


class HeadingCorrectionNode(object):
    """Params (DEFAULTS): ``odom_topic`` ('/odom', raw wheel/gyro odometry),
    ``vo_odom_topic`` ('/rtabmap/odom'), ``corrected_odom_topic``
    ('/blind_navigation/odom_corrected'), ``gyro_calibration_file`` ('': none;
    the YAML written by calibrate_gyro.launch, core/gyro_calibration.py: the
    gyro's scale error), core/gyro_fit's GYRO_FIT_DEFAULTS, core/heading_correction's CORRECTION_DEFAULTS and core/gyro_bias's
    HEADING_CALIBRATION_DEFAULTS: ``window`` (s, 2.0), ``max_gap`` (s, 0.5),
    ``min_windows`` (10), ``max_bias`` (rad/s, 0.01), ``max_scale`` (0.05),
    ``significance`` (sqrt 2 standard errors), ``scale_significance`` (3),
    ``outlier_k`` (5) (and any further ones it defines), and its
    STANDSTILL_DEFAULTS: ``standstill_time`` (s, the longest standstill after
    vision loss, 120; 0: none), ``heading_budget`` (rad, 0.005: it ends as soon
    as bias std x the recording's duration is within this), ``standstill_min``
    (s, 5), ``still_speed``
    (m/s, 0.002), ``still_rate`` (rad/s, 0.03), ``still_settle`` (s, 0.5);
    ``standstill_timeout`` (s after vision loss, sim time; unset: 2 x
    ``standstill_time`` + 5): the standstill ends then even if shorter.
    """

    DEFAULTS = dict(GYRO_FIT_DEFAULTS, **CORRECTION_DEFAULTS, **STANDSTILL_DEFAULTS)
    DEFAULTS.update(odom_topic='/odom', vo_odom_topic='/rtabmap/odom',
                    corrected_odom_topic='/blind_navigation/odom_corrected',
                    gyro_calibration_file='', standstill_timeout=None)

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        self.fit = GyroVisualFit(p)   # validates the params
        self.standstill_time = float(p.standstill_time)
        self.standstill_timeout = standstill_timeout(p)
        if self.standstill_time < 0 or self.standstill_timeout < self.standstill_time:
            raise ValueError('~standstill_time must not be negative and ~standstill_timeout not '
                             'shorter (standstill_time %r, standstill_timeout %r)'
                             % (p.standstill_time, p.standstill_timeout))
        self.scale_prior = self._load_calibration(p.gyro_calibration_file)
        self.corrector = None
        self.standstill = None      # StandstillBias while measuring after vision loss
        self._reference = None      # raw OdomState where the corrected frame starts
        self._lost_at = None        # s (message stamps): when the standstill began
        self._visual = None         # BiasEstimate of visual odometry at vision loss, or None
        self._recording_time = 0.0  # s recorded before vision loss
        self._last_raw = None
        self._frame_id = 'odom'
        self._lock = threading.Lock()
        # Published from the /odom callback, synchronously and without Nagle's delay on
        # either hop: the pi turn and the return close their loops through this relay.
        self.odom_pub = rospy.Publisher(p.corrected_odom_topic, Odometry, queue_size=None)
        self.correction_pub = rospy.Publisher(names.HEADING_CORRECTION, HeadingCorrection,
                                              queue_size=1, latch=True)
        rospy.Subscriber(p.odom_topic, Odometry, self._on_odom, queue_size=5, tcp_nodelay=True)
        rospy.Subscriber(p.vo_odom_topic, Odometry, self._on_vo, queue_size=50)
        rospy.Subscriber(names.VISION_LOST, Empty, self._on_vision_lost, queue_size=1)
        rospy.loginfo('%s: %s -> %s, calibrating against %s until vision is lost, then standing '
                      'still up to %.0f s to measure the gyro bias', rospy.get_name(),
                      p.odom_topic, p.corrected_odom_topic, p.vo_odom_topic, self.standstill_time)

    @staticmethod
    def _load_calibration(path):
        """The gyro calibration in ``path`` (core/gyro_calibration.GyroCalibration), or None:
        none configured, missing (warned) or unusable (error logged)."""
        if not path:
            rospy.loginfo('%s: no ~gyro_calibration_file: the gyro scale is not corrected',
                          rospy.get_name())
            return None
        expanded = os.path.abspath(os.path.expanduser(path))
        if not os.path.exists(expanded):
            rospy.logwarn("%s: no gyro calibration at %s: the pi turn keeps the gyro's scale "
                          'error; run `%s` once to make it', rospy.get_name(), expanded,
                          CALIBRATE_COMMAND)
            return None
        try:
            calibration = load_calibration(expanded)
        except CalibrationError as error:
            rospy.logerr("%s: %s; continuing without it (the gyro scale is not corrected)",
                         rospy.get_name(), error)
            return None
        rospy.loginfo('%s: gyro calibration %s: %s', rospy.get_name(), expanded,
                      calibration.describe())
        return calibration

    def _on_vo(self, msg):
        yaw = None
        if odometry_lost_reason(msg) is None:
            yaw = odom_state_from_msg(msg).yaw
        with self._lock:
            if self.corrector is None and self.standstill is None:
                self.fit.add_visual(msg.header.stamp.to_sec(), yaw)

    def _on_odom(self, msg):
        raw = usable_odom_state(msg, self.params.odom_topic)
        if raw is None:
            return
        result = None
        with self._lock:
            self._last_raw, self._frame_id = raw, msg.header.frame_id or self._frame_id
            if self.corrector is None and self.standstill is None:
                self.fit.add_odometry(raw.stamp, raw.yaw)
            elif self.corrector is None:
                result = self._measure(raw)
            if self.corrector is not None:
                self._correct(msg, self.corrector.update(raw))
        try:
            self.odom_pub.publish(msg)
        except rospy.ROSException:
            pass  # publisher already closed at shutdown
        if result is not None:
            # After this message's relay: whoever hears the correction and then waits for
            # odometry stamped after it gets the corrected frame (rotate_pi does).
            self._publish(*result)

    def _measure(self, raw):
        """One raw OdomState of the standstill; the estimate's result once it is over."""
        if self._reference is None:   # no odometry before vision loss: the frame starts here
            self._set_reference(raw)
        self.standstill.add_odometry(raw)
        if standstill_complete(self._visual, self.standstill, self._recording_time, self.params) \
                or raw.stamp >= self._lost_at + self.standstill_timeout:
            return self._finish()
        return None

    @staticmethod
    def _correct(msg, state):
        """Put the corrected pose and turn rate into ``msg`` (this callback's own copy)."""
        set_pose(msg.pose.pose, state.x, state.y, state.yaw)
        msg.twist.twist.angular.z = state.w

    def _on_vision_lost(self, _msg):
        with self._lock:
            if self.corrector is not None or self.standstill is not None:
                return   # one estimate per run
            self.standstill = StandstillBias(self.params)
            if self._last_raw is not None:
                self._set_reference(self._last_raw)
            result = self._finish() if self.standstill_time <= 0 else None
        if result is not None:
            self._publish(*result)
            return
        rospy.loginfo('%s: vision lost: measuring the gyro bias while the robot stands still '
                      '(until known to %.3f rad over the %.0f s recording, %.0f-%.0f s of still '
                      'odometry)', rospy.get_name(), self.params.heading_budget,
                      self._recording_time, self.params.standstill_min, self.standstill_time)

    def _set_reference(self, raw):
        """Where the corrected frame starts (vision loss); the visual-odometry bias and the
        recording's duration, fixed from then on, for core standstill_complete."""
        self._reference, self._lost_at = raw, raw.stamp
        self._visual, _ = visual_bias(self.fit, self.scale_prior, self.params)
        self._recording_time = self.fit.recording_time(raw.stamp)

    def _finish(self):
        """Estimate (under the lock) and start the corrected frame at the reference;
        returns (correction, reference, standstill summary) for :meth:`_publish`."""
        measured = self.standstill.estimate() if self.standstill_time > 0 else None
        correction = estimate_correction(self.fit, measured, self.scale_prior, self.params)
        self.corrector = CorrectedOdometry(correction)
        reference = self._reference
        if reference is not None:
            self.corrector.update(reference)
        summary = None
        if self.standstill_time > 0:
            summary = (self.standstill.duration, measured)
        return correction, reference, summary

    def _publish(self, correction, reference, summary):
        msg = HeadingCorrection(bias=correction.bias, scale=correction.scale,
                                bias_std=correction.bias_std, scale_std=correction.scale_std,
                                windows=correction.windows, status=correction.status,
                                reason=correction.reason)
        msg.header.stamp = rospy.Time.from_sec(reference.stamp) if reference else rospy.Time.now()
        msg.header.frame_id = self._frame_id
        msg.reference_yaw = reference.yaw if reference else 0.0
        self.correction_pub.publish(msg)
        if summary is not None:
            duration, measured = summary
            if reference is not None and rospy.get_time() >= reference.stamp + self.standstill_timeout:
                rospy.logwarn('%s: the robot stood still only %.1f s within %.0f s of vision '
                              'loss; the bias is measured on that', rospy.get_name(), duration,
                              self.standstill_timeout)
            rospy.loginfo('%s: standstill %.1f s: %s', rospy.get_name(), duration,
                          'bias %.2e +- %.1e rad/s' % (measured.bias, measured.std)
                          if measured else 'no bias measured')
        rospy.loginfo('%s: gyro heading correction %s', rospy.get_name(), correction.describe())

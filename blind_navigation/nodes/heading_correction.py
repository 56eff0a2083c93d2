#!/usr/bin/env python3
"""heading_correction: calibrates the gyro against visual odometry while vision
works and republishes odometry in the corrected frame for the return.

While recording, feeds the raw odometry yaw (``odom_topic``) and RTAB-Map's
visual-odometry yaw (``vo_odom_topic``; a lost message, RTAB-Map's convention,
breaks the current window) to core/heading_calibration.HeadingCalibrator, and
republishes each odometry message unchanged on ``corrected_odom_topic``. On
/blind_navigation/vision_lost it estimates the gyro bias and scale (or no
correction when the data do not determine them), publishes the result latched
on /blind_navigation/heading_correction (blind_navigation/HeadingCorrection:
reference stamp and raw yaw, bias, scale, standard errors, status, reason),
and from then on republishes odometry through
core/heading_calibration.CorrectedOdometry, whose frame equals the raw one at
that moment. rotate_pi, back_travel_server and back_travel_client drive on
``corrected_odom_topic``; back_travel_client expresses the recorded landmarks
in the same frame (core/heading_calibration.correct_landmarks). Stamps come
from the messages, so it works under use_sim_time. One estimate per run: a
later vision_lost is ignored.
"""
import threading

import rospy
from nav_msgs.msg import Odometry
from std_msgs.msg import Empty

from blind_navigation.back_travel_ros import HEADING_CORRECTION_TOPIC, VISION_LOST_TOPIC
from blind_navigation.core.heading_calibration import (HEADING_CALIBRATION_DEFAULTS,
                                                       CorrectedOdometry, HeadingCalibrator)
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros_common import (load_params, odom_state_from_msg, odometry_lost_reason,
                                         set_pose, start_node, usable_odom_state)


class HeadingCorrectionNode(object):
    """Params (DEFAULTS): ``odom_topic`` ('/odom', raw wheel/gyro odometry),
    ``vo_odom_topic`` ('/rtabmap/odom'), ``corrected_odom_topic``
    ('/blind_navigation/odom_corrected'), and core/heading_calibration's
    HEADING_CALIBRATION_DEFAULTS: ``window`` (s, 2.0), ``max_gap`` (s, 0.5),
    ``min_windows`` (10), ``max_bias`` (rad/s, 0.01), ``max_scale`` (0.05),
    ``significance`` (sqrt 2 standard errors), ``max_scale_std`` (0.003),
    ``outlier_k`` (5).
    """

    DEFAULTS = dict(HEADING_CALIBRATION_DEFAULTS, odom_topic='/odom', vo_odom_topic='/rtabmap/odom',
                    corrected_odom_topic='/blind_navigation/odom_corrected')

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        self.calibrator = HeadingCalibrator(p)   # validates the params
        self.corrector = None
        self._last_raw = None
        self._frame_id = 'odom'
        self._lock = threading.Lock()
        # Published from the /odom callback, synchronously and without Nagle's delay on
        # either hop: the pi turn and the return close their loops through this relay.
        self.odom_pub = rospy.Publisher(p.corrected_odom_topic, Odometry, queue_size=None)
        self.correction_pub = rospy.Publisher(HEADING_CORRECTION_TOPIC, HeadingCorrection,
                                              queue_size=1, latch=True)
        rospy.Subscriber(p.odom_topic, Odometry, self._on_odom, queue_size=5, tcp_nodelay=True)
        rospy.Subscriber(p.vo_odom_topic, Odometry, self._on_vo, queue_size=50)
        rospy.Subscriber(VISION_LOST_TOPIC, Empty, self._on_vision_lost, queue_size=1)
        rospy.loginfo('%s: %s -> %s, calibrating against %s until vision is lost', rospy.get_name(),
                      p.odom_topic, p.corrected_odom_topic, p.vo_odom_topic)

    def _on_vo(self, msg):
        yaw = None
        if odometry_lost_reason(msg) is None:
            yaw = odom_state_from_msg(msg).yaw
        with self._lock:
            if self.corrector is None:
                self.calibrator.add_visual(msg.header.stamp.to_sec(), yaw)

    def _on_odom(self, msg):
        raw = usable_odom_state(msg, self.params.odom_topic)
        if raw is None:
            return
        with self._lock:
            self._last_raw, self._frame_id = raw, msg.header.frame_id or self._frame_id
            if self.corrector is None:
                self.calibrator.add_odometry(raw.stamp, raw.yaw)
            else:
                self._correct(msg, self.corrector.update(raw))
        try:
            self.odom_pub.publish(msg)
        except rospy.ROSException:
            pass  # publisher already closed at shutdown

    @staticmethod
    def _correct(msg, state):
        """Put the corrected pose and turn rate into ``msg`` (this callback's own copy)."""
        set_pose(msg.pose.pose, state.x, state.y, state.yaw)
        msg.twist.twist.angular.z = state.w

    def _on_vision_lost(self, _msg):
        with self._lock:
            if self.corrector is not None:
                return
            correction = self.calibrator.estimate()
            self.corrector = CorrectedOdometry(correction)
            reference = self._last_raw
            if reference is not None:
                self.corrector.update(reference)
        msg = HeadingCorrection(bias=correction.bias, scale=correction.scale,
                                bias_std=correction.bias_std, scale_std=correction.scale_std,
                                windows=correction.windows, status=correction.status,
                                reason=correction.reason)
        msg.header.stamp = rospy.Time.from_sec(reference.stamp) if reference else rospy.Time.now()
        msg.header.frame_id = self._frame_id
        msg.reference_yaw = reference.yaw if reference else 0.0
        self.correction_pub.publish(msg)
        rospy.loginfo('%s: gyro heading correction %s', rospy.get_name(), correction.describe())


def main():
    start_node('heading_correction', HeadingCorrectionNode)
    rospy.spin()


if __name__ == '__main__':
    main()

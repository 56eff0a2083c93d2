"""calibrate_gyro: the one-off gyro scale calibration (core/gyro_calibration.py) as a node.

Spins the robot in place ``turns`` full turns counter-clockwise, pauses, and as
many clockwise (core/gyro_calibration.SpinCalibration), publishing on
``cmd_vel_topic`` while feeding the odometry yaw (``odom_topic``) and RTAB-Map's
visual-odometry yaw (``vo_odom_topic``; a lost message breaks the current
window) to its GyroVisualFit. When the spins are done it fits the gyro's
scale error and writes it to ``calibration_file`` (atomically; an existing file
is first copied to ``<calibration_file>.previous``), which heading_correction
reads at mission start. On any failure (a turn over its time allowance, a
calibration the data do not determine, odometry older than ``odom_timeout``, a
Kobuki bumper/cliff/wheel-drop event, shutdown) the robot is stopped at once,
the reason is logged as an error and the file is left untouched. The node then
exits: status 0 on success, 1 on failure; it always ends with zero velocity.
Stamps come from the messages and the loop is a rospy.Rate, so it works under
use_sim_time.
"""
import os
import shutil
import threading
import time

import rospy
from nav_msgs.msg import Odometry

from blind_navigation import names
from blind_navigation.ros.back_travel_common import LatestOdom, SafetyMonitor, VelocityOutput
from blind_navigation.core.gyro_calibration import (SPIN_DEFAULTS, CalibrationError, SpinCalibration,
                                                    save_calibration)
from blind_navigation.core.gyro_fit import GYRO_FIT_DEFAULTS
from blind_navigation.core.heading_correction import CORRECTION_DEFAULTS
from blind_navigation.ros.common import load_params, odom_state_from_msg, odometry_lost_reason


class CalibrateGyro(object):
    """Params (DEFAULTS): ``odom_topic`` ('/odom'), ``vo_odom_topic`` ('/rtabmap/odom'),
    ``cmd_vel_topic`` ('/cmd_vel_mux/input/teleop'), ``calibration_file``
    ('~/.ros/blind_navigation/gyro_calibration.yaml'), ``control_rate`` (Hz, 50),
    ``odom_timeout`` (s, 0.4), ``start_timeout`` (s of wall time to wait for the
    first odometry, 30), ``bumper_topic`` / ``cliff_topic`` / ``wheel_drop_topic``
    (Kobuki's /mobile_base/events/*); core/gyro_calibration's SPIN_DEFAULTS:
    ``turns`` (5 each way), ``max_w`` (rad/s, 0.6, also the output clamp; linear
    velocity is clamped to 0), ``pause`` (s, 3), ``required_scale_std`` (0.002);
    core/gyro_fit's GYRO_FIT_DEFAULTS (``window``,
    ``max_gap``, ``min_windows``, ``outlier_k``, ``max_scale``, ...).
    """

    DEFAULTS = dict(SPIN_DEFAULTS, **GYRO_FIT_DEFAULTS, max_scale=CORRECTION_DEFAULTS['max_scale'], odom_topic='/odom',
                    vo_odom_topic='/rtabmap/odom', cmd_vel_topic='/cmd_vel_mux/input/teleop',
                    calibration_file='~/.ros/blind_navigation/gyro_calibration.yaml',
                    control_rate=50.0, odom_timeout=0.4, start_timeout=30.0,
                    **{kind + '_topic': topic for kind, topic in names.SAFETY_EVENTS.items()})

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        if p.control_rate <= 0 or p.odom_timeout <= 0 or p.start_timeout <= 0:
            raise ValueError('~control_rate, ~odom_timeout and ~start_timeout must be positive')
        self.path = os.path.abspath(os.path.expanduser(p.calibration_file))
        self.spin = SpinCalibration(p)   # validates the spin and calibrator params
        self._lock = threading.Lock()
        self._tripped = None
        self.output = VelocityOutput(p.cmd_vel_topic, 0.0, self.spin.max_w)
        self.safety = SafetyMonitor({kind: getattr(p, kind + '_topic') for kind in names.SAFETY_EVENTS},
                                    self._on_trip)
        rospy.Subscriber(p.vo_odom_topic, Odometry, self._on_vo, queue_size=50)
        self.odom = LatestOdom(p.odom_topic, self._on_odom)

    def _on_odom(self, state, _msg):
        with self._lock:
            self.spin.fit.add_odometry(state.stamp, state.yaw)

    def _on_vo(self, msg):
        yaw = odom_state_from_msg(msg).yaw if odometry_lost_reason(msg) is None else None
        with self._lock:
            self.spin.fit.add_visual(msg.header.stamp.to_sec(), yaw)

    def _on_trip(self, reason):
        self._tripped = reason
        self.output.halt('safety: ' + reason)

    def run(self):
        """Spin, fit and save; True on success. Always ends with zero velocity."""
        try:
            reason = self._spin()
            if not reason:
                with self._lock:
                    calibration = self.spin.result()
                self._save(calibration)
        except CalibrationError as error:
            reason = str(error)
        except (OSError, rospy.ROSInterruptException) as error:
            reason = '%s: %s' % (type(error).__name__, error)
        finally:
            self.output.halt('calibration over')
        if reason:
            rospy.logerr('%s: gyro calibration FAILED, %s left untouched: %s',
                         rospy.get_name(), self.path, reason)
            return False
        rospy.loginfo('%s: gyro calibration %s written to %s', rospy.get_name(),
                      calibration.describe(), self.path)
        return True

    def _spin(self):
        """Drive the spins; '' when done, else why they stopped."""
        p = self.params
        deadline = time.monotonic() + p.start_timeout
        # Under use_sim_time, odometry can arrive before this node's first /clock
        # message (time 0): wait for the clock too, or the first check after the
        # clock jumps would find that odometry stale.
        while rospy.Time.now().is_zero() or self.odom.fresh(p.odom_timeout) is None:
            if rospy.is_shutdown() or time.monotonic() > deadline:
                return 'no odometry before starting: %s' % self.odom.describe_missing(p.odom_timeout)
            time.sleep(0.05)
        rospy.loginfo('%s: spinning %.1f turns each way at %.2f rad/s against %s', rospy.get_name(),
                      self.spin.turns, self.spin.max_w, p.vo_odom_topic)
        rate = rospy.Rate(p.control_rate)
        while not self.spin.done:
            if rospy.is_shutdown():
                return 'node shutdown before the spins were done (%s)' % self.spin.progress
            if self._tripped or self.safety.active:
                return 'safety stop: %s' % (self._tripped or ', '.join(self.safety.active))
            odom = self.odom.fresh(p.odom_timeout)
            if odom is None:
                return self.odom.describe_missing(p.odom_timeout)
            v, w = self.spin.step(odom)
            if self.spin.failed:
                return self.spin.failed
            self.output.publish(v, w)
            rate.sleep()
        return ''

    def _save(self, calibration):
        """Keep an existing file as ``.previous``, then write the new one atomically."""
        if os.path.exists(self.path):
            shutil.copy2(self.path, self.path + '.previous')
            rospy.loginfo('%s: previous calibration kept as %s.previous', rospy.get_name(), self.path)
        save_calibration(self.path, calibration, self.spin.turns)

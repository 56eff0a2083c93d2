"""calibrate_gyro: the one-off gyro scale calibration (core/gyro_calibration.py): ``turns``
spins each way fitting odometry against visual-odometry yaw, then ``calibration_file`` written
atomically (the old one kept as ``.previous``); on failure the robot stops, the file stays."""
import os
import shutil
import threading
import time

import rospy

from blind_navigation import names
from blind_navigation.core import drive, mission_state, outcome
from blind_navigation.core.allowance import DRIVE
from blind_navigation.core.gyro_calibration import CalibrationError, SpinCalibration, save_calibration
from blind_navigation.core.role_params import CALIBRATE_GYRO
from blind_navigation.core.mission_drive import DONE, FAILED
from blind_navigation.ros.drive_node import DriveNode
from blind_navigation.ros.common import ros_home_file
from blind_navigation.ros.heading_correction import CALIBRATION_FILE
from blind_navigation.ros.mission import Role
from blind_navigation.ros.odometry import visual_yaw


class CalibrateGyro(Role):
    """The calibration routine on ROS (module docstring)."""

    ROLE = mission_state.CALIBRATION_ROLE
    SCHEMA = CALIBRATE_GYRO

    def __init__(self, layer):
        Role.__init__(self, layer)
        self.path = ros_home_file(CALIBRATION_FILE, self.params.calibration_file)
        self.spin = SpinCalibration(self.params)   # validates the spin and fit params
        self.odom = layer.odometry
        self._lock = threading.Lock()
        self._vo_valid = False
        self.driver = DriveNode(self, (0.0, self.spin.max_w), None, False, lambda: 'spin')
        self.odom.add_listener(self.guard(self._on_odom))
        layer.visual_odometry.add_listener(self.guard(self._on_vo), raw=True)
        self.odom.acquire(self.ROLE)
        layer.visual_odometry.acquire(self.ROLE)

    def _on_odom(self, state):
        with self._lock:
            self.spin.fit.add_odometry(state.stamp, state.yaw)

    def _on_vo(self, wire):
        yaw = visual_yaw(wire)
        with self._lock:
            self._vo_valid = self._vo_valid or yaw is not None
            self.spin.fit.add_visual(wire.stamp, yaw)

    def run(self):
        """Spin, fit and save; True on success. Always ends with zero velocity."""
        try:
            reason = self._spin()
            if not reason:
                with self._lock:
                    calibration = self.spin.result()
                if os.path.exists(self.path):     # kept as .previous, the new one written atomically
                    shutil.copy2(self.path, self.path + '.previous')
                    self.log.info('previous calibration kept as %s.previous', self.path)
                save_calibration(self.path, calibration, self.spin.turns)
        except CalibrationError as error:
            reason = str(error)
        except (OSError, rospy.ROSInterruptException) as error:
            reason = '%s: %s' % (type(error).__name__, error)
        finally:
            self.driver.output.halt('calibration over')
        if reason:
            self.log.error('gyro calibration FAILED, %s left untouched: %s', self.path, reason)
            return False
        self.log.info('gyro calibration %s written to %s', calibration.describe(), self.path)
        return True

    def _spin(self):
        """Drive the spins; '' when done, else why they stopped."""
        p = self.params
        deadline = time.monotonic() + p.start_timeout
        # the clock too: under use_sim_time odometry may come before the first /clock
        while (rospy.Time.now().is_zero() or not self._vo_valid) and not rospy.is_shutdown() \
                and time.monotonic() <= deadline:
            time.sleep(0.05)
        if not self._vo_valid:
            return ('no valid visual odometry on %s within %.0f s: the calibration needs '
                    "RTAB-Map's visual odometry running and tracking (see the README, "
                    'TurtleBot2 + RTAB-Map); not spinning' % (rospy.resolve_name(names.VO_ODOM), p.start_timeout))
        if rospy.Time.now().is_zero() or self.odom.wait_fresh(
                p.odom_timeout, max(0.0, deadline - time.monotonic())) is None:
            return 'no odometry before starting: %s' % self.odom.describe_missing(p.odom_timeout)
        self.log.info('spinning %.1f turns each way at %.2f rad/s against %s', self.spin.turns,
                      self.spin.max_w, rospy.resolve_name(names.VO_ODOM))
        self.driver.start(_Spins(self.spin, self.driver.feed, p.odom_timeout))
        for now, jump in self.driver.ticks():
            ended = self.driver.step(now, jump)
            if ended is not None and ended.kind != drive.CANCELLED:
                return ended.reason
        return 'node shutdown before the spins were done (%s)' % self.spin.progress


class _Spins(object):
    """The calibration's spins as a drive of ros/drive_node (stale odometry ends them at once)."""

    def __init__(self, spin, feed, odom_timeout):
        self.spin, self.feed, self.cycle = spin, feed, drive.DriveCycle(None, odom_timeout)
        self.phase, self.reason, self.code = 'spin', '', outcome.NONE
        self.resumed = lambda seconds: None

    def where(self):
        return 'the spins'

    def step(self, now, inputs):
        decision, odom, message = self.feed(self.cycle)
        command = self.spin.step(odom) if decision == DRIVE else (0.0, 0.0)
        self.reason = self.spin.failed if decision == DRIVE else message or 'no fresh odometry'
        self.phase = FAILED if self.reason else DONE if self.spin.done else self.phase
        return command

"""The heading correction: while recording, gyro fitted against visual-odometry yaw; in
``rotating`` the bias measured standing still; the correction latched on ``heading_correction``
for the drivers' feeds (docs/back_travel.md, "Gyro heading correction")."""
import datetime
import os
import threading

import rospy

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.gyro_bias import standstill_timeout
from blind_navigation.core.gyro_calibration import CalibrationError, load_calibration
from blind_navigation.core.gyro_fit import GyroVisualFit
from blind_navigation.core.mission_record import Standstill
from blind_navigation.core.role_params import HEADING_CORRECTION
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import ros_home_file
from blind_navigation.ros.mission import Role
from blind_navigation.ros.odometry import visual_yaw

#: How to make the gyro calibration file; where it is when ``gyro_calibration_file`` is empty.
CALIBRATE_COMMAND = 'roslaunch blind_navigation calibrate_gyro.launch'
CALIBRATION_FILE = os.path.join('blind_navigation', 'gyro_calibration.yaml')


def scale_prior(path, log):
    """The GyroCalibration at ``path``, or None: missing (warned) or unusable (logged)."""
    if not os.path.exists(path):
        log.warn("no gyro calibration at %s: the pi turn keeps the gyro's scale error; run `%s` "
                 'once to make it', path, CALIBRATE_COMMAND)
        return None
    try:
        calibration = load_calibration(path)
    except (CalibrationError, OSError) as error:
        log.error('%s; continuing without it (the gyro scale is not corrected)', error)
        return None
    log.info('gyro calibration %s: %s', path, calibration.describe())
    return calibration


def correction_message(correction, reference, frame_id):
    """The HeadingCorrection of a GyroCorrection whose frame starts at the raw ``reference``
    (None: now, at the origin) in ``frame_id``."""
    msg = HeadingCorrection(**correction._asdict())
    msg.header.stamp = rospy.Time.from_sec(reference.stamp) if reference else rospy.Time.now()
    msg.header.frame_id = frame_id
    if reference is not None:
        msg.reference_x, msg.reference_y, msg.reference_yaw = reference.x, reference.y, reference.yaw
    return msg


class HeadingCorrectionRole(Role):
    """Module docstring."""

    ROLE = 'heading_correction'
    SCHEMA = HEADING_CORRECTION

    def __init__(self, layer):
        Role.__init__(self, layer)
        p, guard = self.params, self.guard
        self.calibration_path = ros_home_file(CALIBRATION_FILE, p.gyro_calibration_file)
        self.scale_prior = scale_prior(self.calibration_path, self.log)
        self._fresh()
        self._vo_last = None        # rospy time of the last visual odometry (diagnostics)
        self._lock = threading.Lock()
        self.correction_pub = rospy.Publisher(names.HEADING_CORRECTION, HeadingCorrection,
                                              queue_size=1, latch=True)
        self._odom_listener = guard(self._on_odom)    # removed at the standstill's end
        layer.visual_odometry.add_listener(guard(self._on_vo), raw=True)
        self._listen()
        self.follow('heading correction: visual odometry')
        layer.diagnostics.add('heading correction: gyro calibration', lambda stat: calibration_status(
            stat, self.calibration_path, self.scale_prior))
        self.log.info('calibrating the gyro against %s until vision is lost, then standing still '
                      'up to %.0f s to measure its bias', rospy.resolve_name(names.VO_ODOM),
                      p.standstill_time)

    def _fresh(self):
        self.fit = GyroVisualFit(self.params)
        self.lost = False           # vision lost: the standstill measures
        self.standstill = self.reference = None     # Standstill; raw OdomState the frame starts at
        self.result = None          # GyroCorrection once estimated
        self._started = rospy.get_time()

    def _listen(self):
        self.layer.odometry.add_listener(self._odom_listener)
        self.layer.odometry.acquire(self.ROLE)
        self.layer.visual_odometry.acquire(self.ROLE)

    def _on_vo(self, wire):
        self._vo_last, yaw = rospy.get_time(), visual_yaw(wire)
        with self._lock:
            if not self.lost:
                self.fit.add_visual(wire.stamp, yaw)

    def _on_odom(self, state):
        """Recording: the fit's gyro; after vision loss: the standstill, then the correction."""
        with self._lock:
            if not self.lost:
                self.fit.add_odometry(state.stamp, state.yaw)
                return
            if self.result is not None:
                return
            if self.standstill is None:    # no odometry before vision loss: the frame starts here
                self._stand(state)
            self.result = self.standstill.correction(state.stamp, state)
        if self.result is not None:
            self._publish()

    def _new_mission(self):
        with self._lock:
            self._fresh()
        self._listen()
        self.log.info('new mission: calibrating the gyro against visual odometry again')

    def _on_state(self, old, new):
        if old == mission_state.ROTATING and new == mission_state.RECORDING:
            with self._lock:    # vision back before the pi turn: the standstill dropped, the fit goes on
                resumed = self.result is None and self.lost
                if resumed:
                    self.lost, self.standstill = False, None
            if resumed:
                self.layer.visual_odometry.acquire(self.ROLE)
                self.log.info('vision back before the pi turn: standstill dropped, calibrating on')
        if new != mission_state.ROTATING:
            if new in mission_state.TERMINAL:
                self._stop_listening()
            return
        with self._lock:
            if self.lost or self.result is not None:
                return   # one estimate per mission
            self.lost = True
            latest = self.layer.odometry.latest()
            if latest is not None:
                self._stand(latest)
                self.result = self.standstill.correction(latest.stamp)   # standstill_time 0
        self.layer.visual_odometry.release(self.ROLE)
        if self.result is not None:
            self._publish()
            return
        self.log.info('vision lost: measuring the gyro bias while the robot stands still (until '
                      'known to %.3f rad over the recording, %.0f-%.0f s of still odometry)',
                      self.params.heading_budget, self.params.standstill_min,
                      self.params.standstill_time)

    def _stand(self, raw):
        """The standstill from ``raw``, where the corrected frame starts (lock held)."""
        self.reference = raw
        self.standstill = Standstill(self.fit, raw, self.params, self.scale_prior)

    def _publish(self):
        correction, measured = self.result, self.standstill.measurement
        bias = measured.estimate()
        self.correction_pub.publish(correction_message(correction, self.reference,
                                                       self.layer.odometry.frame_id))
        if self.params.standstill_time > 0:
            if rospy.get_time() >= self.standstill.deadline:
                self.log.warn('the robot stood still only %.1f s within %.0f s of vision loss; the '
                              'bias is measured on that', measured.duration,
                              standstill_timeout(self.params))
            self.log.info('standstill %.1f s: %s', measured.duration, 'bias %.2e +- %.1e rad/s'
                          % bias[:2] if bias else 'no bias measured')
        self.log.info('gyro heading correction %s', correction.describe())
        self._stop_listening()
        self.layer.diagnostics.now()

    def _stop_listening(self):
        self.layer.odometry.remove_listener(self._odom_listener)
        self.layer.odometry.release(self.ROLE)
        self.layer.visual_odometry.release(self.ROLE)

    def _diagnose(self, stat):
        vo_status(stat, self.lost, self._vo_last, self._started, self.params.vo_timeout, len(self.fit.rows))


def vo_status(stat, lost, heard, since, timeout, windows):
    """The visual odometry's status: ``lost`` (no longer used), last ``heard`` (rospy time, None:
    never), the mission ``since``, ``timeout`` (vo_timeout), the fit's ``windows``."""
    now = rospy.get_time()
    age, waited = None if heard is None else now - heard, now - since
    if lost:
        stat.summary(diagnostics.OK, 'vision lost: visual odometry no longer used')
        return
    missing = diagnostics.WARN if waited > timeout else diagnostics.OK
    diagnostics.age_status(stat, 'visual odometry', age, timeout, diagnostics.WARN, missing)
    stat.add('windows', windows)


def calibration_status(stat, path, scale_prior):
    """The gyro calibration's status: its ``path``, ``scale_prior`` (None: unusable)."""
    stat.add('file', path)
    if scale_prior is None:
        stat.summary(diagnostics.WARN, 'no usable gyro calibration: run `%s`' % CALIBRATE_COMMAND)
        return
    modified = datetime.datetime.fromtimestamp(os.path.getmtime(path)) \
        if os.path.exists(path) else None
    stat.add('calibrated', modified.isoformat(timespec='seconds') if modified else '?')
    stat.add('scale error', '%+.5f +- %.5f' % (scale_prior.scale, scale_prior.scale_std))
    stat.summary(diagnostics.OK, 'gyro calibration %s' % scale_prior.describe())

#!/usr/bin/env python3
"""rostest: heading_correction on sim time (heading_correction.test).

60 s of a weaving robot whose odometry heading is a gyro with bias 2e-3 rad/s and
scale error 1 %, visual odometry at 30 Hz (lost for 5 s); then vision is lost (this
node is the mission's owner, both nodes' ~mission_owner: it moves the mission state
from recording to rotating) and the robot stands still (gyro noise 0.003 rad/s per
sample) for ``standstill_time`` (the .test sets 5 s) plus slack, then weaves on for
20 s. Two nodes hear the same data: ``/heading_correction`` (started by the .test, no
calibration file: the scale is not corrected) and ``/heading_correction_calibrated``
(started here, after this test wrote a gyro calibration file with
core/gyro_calibration.save_calibration to a temporary directory; its correction
remapped under /calibrated).

Asserted: no correction is published before the standstill is over, and it is
published once it is, referenced to the last odometry before vision loss; the bias
(visual odometry and standstill fused) is the gyro's within 4 of its stated standard
errors; the calibrated node uses the file's scale (status full, scale equal to the
file's), the plain one none (status bias); afterwards the odometry corrected with
it (core/heading_correction.CorrectedOdometry from the reference on, as the pi turn
and the return do: ros/odometry.OdometryFeed.set_correction) follows the true
heading and turn rate (the plain node's with the gyro's scale error still in them)
while /odom keeps drifting. (The node no longer relays a corrected odometry topic:
the roles correct the odometry themselves.)
"""
import math
import os
import random
import shutil
import subprocess
import tempfile
import time
import unittest

import roslib.packages
import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock, Log
from std_msgs.msg import String

from blind_navigation.core.geometry import OdomState, wrap_angle
from blind_navigation.core.gyro_calibration import GyroCalibration, load_calibration, save_calibration
from blind_navigation.core.heading_correction import CorrectedOdometry
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros.common import set_pose
from blind_navigation.ros.layer import correction_from_message

from waiting import wait_for

BIAS = 2e-3          # rad/s
SCALE = 0.01         # gyro scale error: measured rate = (1 + SCALE) true rate + BIAS
NOISE = 0.003        # rad/s per sample while standing still (the Kobuki gyro's datasheet level)
DT = 0.02
LOST = (20.0, 25.0)
CALIBRATED = '/calibrated'
NODES = ('/heading_correction', '/heading_correction_calibrated')
#: What heading_correction logs when the mission moves to rotating (vision lost).
STANDSTILL_LOG = 'measuring the gyro bias while the robot stands still'
#: Calibration written to the temporary file: the gyro's true scale error, known to 5e-4.
FILE_CALIBRATION = GyroCalibration(SCALE, 5e-4, 1e-3, 1e-4, 60)


def odometry(stamp, frame, x, y, yaw, w, v=0.1, covariance=1e-4):
    msg = Odometry()
    msg.header.stamp, msg.header.frame_id = rospy.Time.from_sec(stamp), frame
    set_pose(msg.pose.pose, x, y, yaw)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = v, w
    for i in (0, 7, 14, 21, 28, 35):
        msg.pose.covariance[i] = msg.twist.covariance[i] = covariance
    return msg


class Listener(object):
    """The correction of one heading_correction node."""

    def __init__(self, prefix):
        self.correction, self.correction_at = None, None
        rospy.Subscriber(prefix + '/blind_navigation/heading_correction', HeadingCorrection,
                         self._on_correction)

    def _on_correction(self, msg):
        self.correction, self.correction_at = msg, rospy.get_time()

    def corrected(self, raw_states):
        """The last of ``raw_states`` (OdomStates) in this node's corrected frame, as the
        roles compute it: from the correction's reference on."""
        correction, reference = correction_from_message(self.correction)
        corrector = CorrectedOdometry(correction)
        corrector.update(reference)
        for state in raw_states:
            if state.stamp > reference.stamp:
                corrector.update(state)
        return corrector.state


class HeadingCorrectionTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_heading_correction')
        cls.standstill_time = float(rospy.get_param('/heading_correction/standstill_time'))
        cls.random = random.Random(1)
        cls.directory = tempfile.mkdtemp(prefix='heading_correction_test-')
        cls.calibration_file = save_calibration(os.path.join(cls.directory, 'gyro_calibration.yaml'),
                                                FILE_CALIBRATION, turns=3)
        cls.node = cls.start_calibrated_node()
        try:
            cls.run_mission()
        finally:
            cls.node.terminate()
            cls.node.wait(timeout=10.0)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.directory, ignore_errors=True)

    @classmethod
    def start_calibrated_node(cls):
        found = roslib.packages.find_node('blind_navigation', 'heading_correction.py')
        if not found:
            raise AssertionError('heading_correction.py not found in package blind_navigation')
        return subprocess.Popen([
            found[0], '__name:=heading_correction_calibrated',
            '_gyro_calibration_file:=' + cls.calibration_file,
            '_standstill_time:=%r' % cls.standstill_time,
            '_mission_owner:=%s' % rospy.get_name(),
            '/blind_navigation/heading_correction:=%s/blind_navigation/heading_correction' % CALIBRATED])

    @classmethod
    def run_mission(cls):
        cls.clock = rospy.Publisher('/clock', Clock, queue_size=10)
        cls.odom = rospy.Publisher('/odom', Odometry, queue_size=100)
        cls.vo = rospy.Publisher('/rtabmap/odom', Odometry, queue_size=100)
        cls.state = rospy.Publisher('/blind_navigation/state', String, queue_size=1, latch=True)
        cls.logs = []
        rospy.Subscriber('/rosout', Log, cls.logs.append, queue_size=100)
        cls.plain, cls.calibrated = Listener(''), Listener(CALIBRATED)
        listeners = (cls.plain, cls.calibrated)
        wait_for(lambda: all(pub.get_num_connections() >= 2
                             for pub in (cls.odom, cls.vo, cls.clock, cls.state)),
                 'both heading_correction nodes subscribed to /clock, /odom, /rtabmap/odom and '
                 'the mission state')
        cls.state.publish(String(data='recording'))
        cls.t = cls.true_yaw = cls.gyro_yaw = cls.noise_yaw = cls.x = 0.0
        cls.next_vo = 0.0
        cls.lost_at, cls.raw_after_loss = None, []
        cls.drive(60.0)
        # vision lost: the reference is the last odometry, at cls.t. Nothing observable
        # tells that a node has handled its last odometry message; with the clock and
        # the odometry paused, 1 s of wall time is far more than it takes.
        time.sleep(1.0)
        cls.lost_at, cls.true_at_loss, cls.gyro_at_loss = cls.t, cls.true_yaw, cls.gyro_yaw
        cls.state.publish(String(data='rotating'))
        wait_for(lambda: all(any(m.name == node and STANDSTILL_LOG in m.msg for m in list(cls.logs))
                             for node in NODES),
                 'both nodes start their standstill when the mission moves to rotating')
        cls.drive(cls.standstill_time - 1.0, still=True)
        time.sleep(0.5)   # a correction published too early would have arrived by now
        cls.during_standstill = [listener.correction for listener in listeners]
        cls.drive(2.5, still=True)   # past standstill_time + still_settle (0.5 s)
        for listener, name in zip(listeners, NODES):
            wait_for(lambda: listener.correction is not None,
                     'latched heading correction from %s after a standstill of %.1f s'
                     % (name, cls.standstill_time))
        cls.drive(20.0)

    @classmethod
    def drive(cls, seconds, still=False):
        """Publish ``seconds`` of sim time (about 5x real time): weaving with visual
        odometry, or (``still``) standing with a noisy gyro and vision lost."""
        for _ in range(int(round(seconds / DT))):
            w = 0.0 if still else 0.4 * math.sin(2 * math.pi * cls.t / 20.0)
            noise = cls.random.gauss(0.0, NOISE) if still else 0.0
            gyro_w = (1.0 + SCALE) * w + BIAS + noise
            cls.w = w
            cls.t += DT
            cls.true_yaw += w * DT
            cls.gyro_yaw += gyro_w * DT
            cls.noise_yaw += noise * DT
            cls.x += 0.0 if still else 0.1 * DT
            cls.clock.publish(Clock(clock=rospy.Time.from_sec(cls.t)))
            v = 0.0 if still else 0.1
            cls.odom.publish(odometry(cls.t, 'odom', cls.x, 0.0, wrap_angle(cls.gyro_yaw), gyro_w, v=v))
            if cls.lost_at is not None:
                cls.raw_after_loss.append(OdomState(cls.x, 0.0, wrap_angle(cls.gyro_yaw), v, gyro_w,
                                                    cls.t))
            while not still and cls.next_vo <= cls.t + 1e-9:
                if LOST[0] <= cls.next_vo < LOST[1]:
                    msg = odometry(cls.next_vo, 'vo_odom', 0.0, 0.0, 0.0, 0.0, covariance=9999.0)
                    msg.pose.pose.orientation.w = 0.0
                else:
                    msg = odometry(cls.next_vo, 'vo_odom', 0.0, 0.0, wrap_angle(cls.true_yaw), w)
                cls.vo.publish(msg)
                cls.next_vo += 1.0 / 30.0
            if still:
                cls.next_vo = cls.t
            time.sleep(DT / 5.0)

    def test_no_correction_before_the_standstill_ends(self):
        for correction, name in zip(self.during_standstill, ('plain', 'calibrated')):
            self.assertIsNone(correction, '%s: correction published %.1f s into a %.1f s standstill'
                              % (name, self.standstill_time - 1.0, self.standstill_time))

    def test_correction_follows_the_standstill(self):
        for listener in (self.plain, self.calibrated):
            c = listener.correction
            self.assertAlmostEqual(c.header.stamp.to_sec(), self.lost_at, places=6,
                                   msg='the reference is the last odometry before vision loss')
            self.assertGreaterEqual(listener.correction_at, self.lost_at + self.standstill_time,
                                    'correction at sim %.2f, before the standstill ended (lost at %.2f)'
                                    % (listener.correction_at, self.lost_at))

    def test_bias_within_its_standard_error(self):
        for listener in (self.plain, self.calibrated):
            c = listener.correction
            self.assertIn(c.status, ('full', 'bias'), c.reason)
            self.assertGreater(c.bias_std, 0.0, '%r' % c)
            self.assertLess(c.bias_std, 2e-4, 'standstill and visual odometry determine the bias: %r' % c)
            self.assertLess(abs(c.bias - BIAS), 4 * c.bias_std, '%r' % c)
            self.assertLessEqual(c.windows, 28, 'no window spans the lost stretch')

    def test_calibration_file_gives_the_scale(self):
        c = self.calibrated.correction
        expected = load_calibration(self.calibration_file)
        self.assertEqual(c.status, 'full', c.reason)
        self.assertEqual(c.scale, expected.scale)
        self.assertEqual(c.scale_std, expected.scale_std)
        plain = self.plain.correction
        self.assertEqual((plain.status, plain.scale), ('bias', 0.0),
                         'without a calibration the mission does not set the scale: %r' % plain)
        self.assertIn('no gyro calibration', plain.reason)

    def test_corrected_odometry_follows_the_truth(self):
        true_turn = self.true_yaw - self.true_at_loss
        # the gyro's white noise while standing is a real heading error no correction removes
        noise_turn = self.noise_yaw / (1.0 + SCALE)
        # the plain node corrects the bias only: its heading keeps the gyro's scale error
        for listener, name, scale in ((self.plain, 'plain', SCALE), (self.calibrated, 'calibrated', 0.0)):
            last = listener.corrected(self.raw_after_loss)
            turned = wrap_angle(last.yaw - listener.correction.reference_yaw)
            expected = (1.0 + scale) * (true_turn + noise_turn)
            self.assertLess(abs(wrap_angle(turned - expected)), 0.005,
                            '%s: corrected heading turned %.4f rad, expected %.4f (truth %.4f)'
                            % (name, turned, expected, true_turn))
            self.assertAlmostEqual(last.w, (1.0 + scale) * self.w, delta=1e-3,
                                   msg='%s: turn rate without the bias' % name)
        raw_turn = self.gyro_yaw - self.gyro_at_loss - self.noise_yaw
        self.assertGreater(abs(wrap_angle(raw_turn - true_turn)), 0.03,
                           'raw odometry drifted by the bias')


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'heading_correction_test', HeadingCorrectionTest)

#!/usr/bin/env python3
"""rostest: heading_correction on sim time. 60 s of a weaving robot whose odometry
heading is a gyro with bias 2e-3 rad/s, visual odometry at 30 Hz (lost for 5 s);
before vision_lost the corrected topic repeats /odom; after it the latched
HeadingCorrection carries the bias and the corrected heading and turn rate
follow the true ones while /odom keeps drifting."""
import math
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from std_msgs.msg import Empty

from blind_navigation.core.geometry import wrap_angle, yaw_from_quaternion
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros_common import set_pose

from waiting import wait_for

BIAS = 2e-3
DT = 0.02
LOST = (20.0, 25.0)


def odometry(stamp, frame, x, y, yaw, w, covariance=1e-4):
    msg = Odometry()
    msg.header.stamp, msg.header.frame_id = rospy.Time.from_sec(stamp), frame
    set_pose(msg.pose.pose, x, y, yaw)
    msg.twist.twist.linear.x, msg.twist.twist.angular.z = 0.1, w
    for i in (0, 7, 14, 21, 28, 35):
        msg.pose.covariance[i] = msg.twist.covariance[i] = covariance
    return msg


def yaw_of(msg):
    q = msg.pose.pose.orientation
    return yaw_from_quaternion(q.x, q.y, q.z, q.w)


class HeadingCorrectionTest(unittest.TestCase):

    def setUp(self):
        rospy.init_node('test_heading_correction')
        self.clock = rospy.Publisher('/clock', Clock, queue_size=10)
        self.odom = rospy.Publisher('/odom', Odometry, queue_size=100)
        self.vo = rospy.Publisher('/rtabmap/odom', Odometry, queue_size=100)
        self.lost = rospy.Publisher('/blind_navigation/vision_lost', Empty, queue_size=1, latch=True)
        self.corrected, self.correction = [], None
        rospy.Subscriber('/blind_navigation/odom_corrected', Odometry, self.corrected.append)
        rospy.Subscriber('/blind_navigation/heading_correction', HeadingCorrection,
                         lambda msg: setattr(self, 'correction', msg))
        wait_for(lambda: self.odom.get_num_connections() and self.vo.get_num_connections()
                 and self.clock.get_num_connections() and self.lost.get_num_connections(),
                 'heading_correction subscribed to /clock, /odom, /rtabmap/odom, vision_lost')
        self.t = self.true_yaw = self.gyro_yaw = 0.0
        self.next_vo = 0.0

    def drive(self, seconds):
        """Publish ``seconds`` of sim time (about 5x real time)."""
        for _ in range(int(round(seconds / DT))):
            w = self.w = 0.4 * math.sin(2 * math.pi * self.t / 20.0)
            self.t += DT
            self.true_yaw += w * DT
            self.gyro_yaw += (w + BIAS) * DT
            self.clock.publish(Clock(clock=rospy.Time.from_sec(self.t)))
            self.odom.publish(odometry(self.t, 'odom', 0.1 * self.t, 0.0, wrap_angle(self.gyro_yaw),
                                       w + BIAS))
            while self.next_vo <= self.t + 1e-9:
                if LOST[0] <= self.next_vo < LOST[1]:
                    msg = odometry(self.next_vo, 'vo_odom', 0.0, 0.0, 0.0, 0.0, covariance=9999.0)
                    msg.pose.pose.orientation.w = 0.0
                else:
                    msg = odometry(self.next_vo, 'vo_odom', 0.0, 0.0, wrap_angle(self.true_yaw), w)
                self.vo.publish(msg)
                self.next_vo += 1.0 / 30.0
            time.sleep(DT / 5.0)

    def test_bias_estimated_and_odometry_corrected(self):
        self.drive(60.0)
        wait_for(lambda: self.corrected and self.corrected[-1].header.stamp.to_sec() >= self.t - 1e-6,
                 'corrected odometry up to sim t %.2f' % self.t)
        self.assertAlmostEqual(yaw_of(self.corrected[-1]), wrap_angle(self.gyro_yaw), places=6,
                               msg='before vision loss the corrected topic repeats /odom')
        self.lost.publish(Empty())
        wait_for(lambda: self.correction is not None, 'latched /blind_navigation/heading_correction')
        c = self.correction
        self.assertIn(c.status, ('full', 'bias'), c.reason)
        self.assertLess(abs(c.bias - BIAS), max(4 * c.bias_std, 1e-4), '%r' % c)
        self.assertLessEqual(c.windows, 28, 'no window spans the lost stretch')
        start_true, start_gyro = self.true_yaw, self.gyro_yaw
        self.drive(20.0)
        wait_for(lambda: self.corrected[-1].header.stamp.to_sec() >= self.t - 1e-6,
                 'corrected odometry up to sim t %.2f' % self.t)
        last = self.corrected[-1]
        turned = wrap_angle(yaw_of(last) - c.reference_yaw)
        self.assertLess(abs(wrap_angle(turned - (self.true_yaw - start_true))), 0.005,
                        'corrected heading follows the true turn')
        self.assertGreater(abs(wrap_angle(self.gyro_yaw - start_gyro - (self.true_yaw - start_true))),
                           0.03, 'raw odometry drifted by the bias')
        self.assertAlmostEqual(last.twist.twist.angular.z, self.w, delta=1e-3,
                               msg='turn rate without the bias')


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'heading_correction_test', HeadingCorrectionTest)

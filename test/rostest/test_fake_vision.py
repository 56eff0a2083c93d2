#!/usr/bin/env python3
"""rostest: each vision-failure mode of the fake TurtleBot looks as specified (``~mode``):
dark = black images + lost VO, stall = nothing published, lost = good images + lost VO;
failure comes at ``vision_fail_at`` and /fake_turtlebot/set_vision restores and fails it."""
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image
from std_srvs.srv import SetBool

import waiting

TIMEOUT = 20.0
LOST_DIAGONAL = [9999.0] * 6
DIAGONAL = (0, 7, 14, 21, 28, 35)


def wait_for(condition, what, timeout=TIMEOUT):
    waiting.wait_for(condition, 'waiting for ' + what, timeout)


def is_lost(odom):
    q = odom.pose.pose.orientation
    return ((q.x, q.y, q.z, q.w) == (0, 0, 0, 0) and odom.pose.pose.position.x == 0.0
            and [odom.pose.covariance[i] for i in DIAGONAL] == LOST_DIAGONAL
            and [odom.twist.covariance[i] for i in DIAGONAL] == LOST_DIAGONAL)


def is_black(image):
    return not any(image.data)


class FakeVisionTest(unittest.TestCase):

    def setUp(self):
        self.mode = rospy.get_param('~mode')
        self.fail_at = rospy.get_param('~vision_fail_at')
        self.images, self.odoms = [], []
        rospy.Subscriber('/camera/rgb/image_rect_color', Image, self.images.append)
        rospy.Subscriber('/rtabmap/odom', Odometry, self.odoms.append)

    def window(self, messages, start, end):
        return [m for m in messages if start <= m.header.stamp.to_sec() < end]

    def check_failed(self, start, end):
        images, odoms = self.window(self.images, start, end), self.window(self.odoms, start, end)
        if self.mode == 'stall':
            self.assertEqual((len(images), len(odoms)), (0, 0), 'stall still publishes')
            return
        self.assertGreater(len(images), 10, 'camera stopped in mode %s' % self.mode)
        self.assertGreater(len(odoms), 10, 'VO stopped in mode %s' % self.mode)
        self.assertTrue(all(is_lost(o) for o in odoms), 'VO not in the lost convention')
        self.assertEqual(all(is_black(i) for i in images), self.mode == 'dark')
        self.assertFalse(self.mode == 'lost' and any(is_black(i) for i in images))

    def check_working(self, start, end):
        images, odoms = self.window(self.images, start, end), self.window(self.odoms, start, end)
        self.assertGreater(len(images), 10, 'no images while vision works')
        self.assertGreater(len(odoms), 10, 'no VO while vision works')
        self.assertFalse(any(is_lost(o) or is_black(i) for o, i in zip(odoms, images)))

    def test_failure_mode(self):
        now = lambda: rospy.Time.now().to_sec()
        wait_for(lambda: now() > self.fail_at + 2.0, 'sim time past vision_fail_at + 2 s')
        self.check_working(self.fail_at - 1.5, self.fail_at - 0.1)
        self.check_failed(self.fail_at + 0.1, self.fail_at + 1.5)
        rospy.wait_for_service('/fake_turtlebot/set_vision', timeout=TIMEOUT)
        set_vision = rospy.ServiceProxy('/fake_turtlebot/set_vision', SetBool)
        self.assertTrue(set_vision(True).success)
        restored = now()
        wait_for(lambda: now() > restored + 1.7, '1.7 s of sim time after restoring vision')
        self.check_working(restored + 0.2, restored + 1.5)
        self.assertTrue(set_vision(False).success)
        failed = now()
        wait_for(lambda: now() > failed + 1.7, '1.7 s of sim time after failing vision again')
        self.check_failed(failed + 0.2, failed + 1.5)


if __name__ == '__main__':
    rospy.init_node('test_fake_vision')
    rostest.rosrun('blind_navigation', 'test_fake_vision', FakeVisionTest)

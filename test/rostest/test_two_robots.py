#!/usr/bin/env python3
"""rostest (two_robots.test): two fake TurtleBots with the whole layer in two namespaces
on one master. Both missions end home, each robot within max_error of its start (ground
truth), every topic of the layer and of the fakes lives in its robot's namespace (only
ROS's global topics outside), each namespace's odometry comes from its own base, the two
fakes share one /clock and publish TF frames of their own."""
import math
import threading
import unittest

import rosgraph
import rospy
import rostest
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

from blind_navigation import names
from blind_navigation.core.mission_state import TERMINAL

import waiting

#: topics that are global by design: the clock, logging, diagnostics, TF
GLOBAL_TOPICS = {'/clock', '/rosout', '/rosout_agg', '/diagnostics', '/tf', '/tf_static'}
#: s of wall time for the two missions (about 100 s of sim time each at rtf 3, two layers
#: and two fakes on two cores)
MISSION_TIMEOUT = 240.0
#: m: the closed-loop target on the ideal profile (0.05 m) + 50 % for ROS timing, as
#: mission_closed_loop.test
MAX_ERROR = 0.075


class Robot(object):
    """What the test sees of one namespace: its state and its ground-truth start and end."""

    def __init__(self, namespace):
        self.namespace = namespace
        self.state = None
        self.start = self.latest = None
        self._lock = threading.Lock()
        rospy.Subscriber(self.name(names.STATE), String, self._on_state)
        rospy.Subscriber(self.name(names.GROUND_TRUTH), Odometry, self._on_truth, queue_size=1)

    def name(self, relative):
        return '/%s/%s' % (self.namespace, relative)

    def _on_state(self, msg):
        self.state = msg.data

    def _on_truth(self, msg):
        p = msg.pose.pose.position
        with self._lock:
            self.start = self.start or (p.x, p.y)
            self.latest = (p.x, p.y)

    def error(self):
        with self._lock:
            return math.hypot(self.latest[0] - self.start[0], self.latest[1] - self.start[1])


class TwoRobotsTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.robots = [Robot(ns) for ns in rospy.get_param('~robots')]
        cls.frames = set()
        rospy.Subscriber('/tf', TFMessage, cls._on_tf, queue_size=100)
        waiting.wait_for(lambda: all(r.start for r in cls.robots), 'both ground truths', 60.0)
        waiting.wait_for(lambda: all(r.state in TERMINAL for r in cls.robots),
                         'both missions to end (states %s)' % [r.state for r in cls.robots],
                         MISSION_TIMEOUT)

    @classmethod
    def _on_tf(cls, msg):
        cls.frames.update((t.header.frame_id, t.child_frame_id) for t in msg.transforms)

    def test_1_both_robots_come_home(self):
        for robot in self.robots:
            self.assertEqual(robot.state, 'home', '%s ended %s' % (robot.namespace, robot.state))
            self.assertLess(robot.error(), MAX_ERROR, '%s ended %.3f m from its start'
                            % (robot.namespace, robot.error()))

    def test_2_every_topic_is_in_its_robots_namespace(self):
        publishers, subscribers, _ = rosgraph.Master(rospy.get_name()).getSystemState()
        prefixes = tuple('/%s/' % r.namespace for r in self.robots)
        for topic, nodes in publishers + subscribers:
            if topic in GLOBAL_TOPICS:
                continue
            self.assertTrue(topic.startswith(prefixes), 'topic %s outside the robots (%s)' % (topic, nodes))
            namespace = topic.split('/')[1]
            stray = [n for n in nodes if not n.startswith('/%s/' % namespace) and n != rospy.get_name()]
            self.assertEqual(stray, [], '%s: nodes of another namespace: %s' % (topic, stray))

    def test_2b_every_service_is_in_its_robots_namespace(self):
        _, _, services = rosgraph.Master(rospy.get_name()).getSystemState()
        prefixes = tuple('/%s/' % r.namespace for r in self.robots)
        for service, nodes in services:
            if set(nodes) <= {rospy.get_name(), '/rosout'}:
                continue
            self.assertTrue(service.startswith(prefixes), 'service %s outside the robots (%s)' % (service, nodes))

    def test_3_one_clock_and_each_robot_its_own_odometry(self):
        publishers, _, _ = rosgraph.Master(rospy.get_name()).getSystemState()
        by_topic = dict(publishers)
        self.assertEqual(by_topic['/clock'], ['/%s/mobile_base' % self.robots[0].namespace])
        for robot in self.robots:
            self.assertEqual(by_topic[robot.name(names.ODOM)], ['/%s/mobile_base' % robot.namespace])

    def test_4_tf_frames_are_apart(self):
        waiting.wait_for(lambda: self.frames, 'a TF message', 10.0)
        prefixes = tuple('%s/' % r.namespace for r in self.robots)
        for parent, child in self.frames:
            self.assertTrue(parent.startswith(prefixes) and child.startswith(prefixes),
                            'TF %s -> %s has no robot prefix' % (parent, child))
        for robot in self.robots:
            self.assertIn(('%s/odom' % robot.namespace, '%s/base_footprint' % robot.namespace), self.frames)


if __name__ == '__main__':
    rospy.init_node('two_robots_test')
    rostest.rosrun('blind_navigation', 'two_robots', TwoRobotsTest)

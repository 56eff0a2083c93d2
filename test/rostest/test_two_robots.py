#!/usr/bin/env python3
"""rostest (two_robots.test): two fake TurtleBots with the whole layer in two namespaces
on one master, robot1's layer in one process (the default), robot2's in the paper's node
layout (``~paper_layout``). Both missions end home, each robot within max_error of its start
(ground truth), every topic and service of the layers and of the fakes lives in its robot's
namespace (only ROS's global topics outside), each namespace's odometry comes from its own
base, the two fakes share one /clock and publish TF frames of their own.

/diagnostics carries each layer's statuses, named after their nodes in the robot's
namespace ("robot1/blind_navigation: mission", "robot2/back_travel_client: mission"): the
mission (its state), odometry (its age), the landmark file (its size), visual odometry and
the gyro calibration (heading correction, no calibration file: a warning naming
calibrate_gyro) and the vision monitor; every node of each layer publishes on
/diagnostics, and no status is an ERROR."""
import math
import threading
import unittest

import rosgraph
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

from blind_navigation import names
from blind_navigation.core.mission_state import TERMINAL
from blind_navigation.sim.node_common import GROUND_TRUTH

import waiting

#: topics that are global by design: the clock, logging, diagnostics, TF
GLOBAL_TOPICS = {'/clock', '/rosout', '/rosout_agg', '/diagnostics', '/tf', '/tf_static'}
#: s of wall time for the two missions (about 60 s of sim time each at rtf 3, two layers
#: and two fakes on two cores)
MISSION_TIMEOUT = 240.0
#: m: the closed-loop target on the ideal profile (0.05 m) + 50 % for ROS timing, as
#: lane_mission_closed_loop.test
MAX_ERROR = 0.075
#: diagnostic_updater's placeholder when a status is added, before its first check ran
STARTING = 'Node starting up'
#: the node of each role in the paper's layout; in one process they are all blind_navigation
PAPER_NODES = {'back_travel_client': 'back_travel_client', 'heading_correction': 'heading_correction',
               'vision_monitor': 'vision_monitor'}
#: every node of blind_navigation.launch one_process:=false (topic recorder, auto_detect)
PAPER_LAYOUT = ['heading_correction', 'back_travel_server', 'rotate_pi', 'back_travel_client',
                'vision_monitor', 'landmark_saver', 'sampling_publisher']
#: (role, status name after "<node>: ") of what a user must see
EXPECTED = [('back_travel_client', 'mission'), ('back_travel_client', 'odometry'),
            ('back_travel_client', 'landmark file'),
            ('heading_correction', 'heading correction: visual odometry'),
            ('heading_correction', 'heading correction: gyro calibration'),
            ('vision_monitor', 'vision monitor')]


class Robot(object):
    """What the test sees of one namespace: its state, ground-truth start and end, layout."""

    def __init__(self, namespace, paper_layout):
        self.namespace = namespace
        self.node_of = {role: node if paper_layout else 'blind_navigation' for role, node in PAPER_NODES.items()}
        self.layer_nodes = PAPER_LAYOUT if paper_layout else ['blind_navigation']
        self.state = None
        self.start = self.latest = None
        self._lock = threading.Lock()
        rospy.Subscriber(self.name(names.STATE), String, self._on_state)
        rospy.Subscriber(self.name(GROUND_TRUTH), Odometry, self._on_truth, queue_size=1)

    def name(self, relative):
        return '/%s/%s' % (self.namespace, relative)

    def status_name(self, role, what):
        return '%s/%s: %s' % (self.namespace, self.node_of[role], what)

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
        paper = set(rospy.get_param('~paper_layout', []))
        cls.robots = [Robot(ns, ns in paper) for ns in rospy.get_param('~robots')]
        cls.frames = set()
        cls.lock = threading.Lock()
        cls.statuses = {}       # status name -> [DiagnosticStatus, ...] in arrival order
        cls.publishers = {}     # callerid -> the most statuses in one of its arrays
        rospy.Subscriber('/tf', TFMessage, cls._on_tf, queue_size=100)
        rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diagnostics, queue_size=100)
        waiting.wait_for(lambda: all(r.start for r in cls.robots), 'both ground truths', 60.0)
        waiting.wait_for(lambda: all(r.state in TERMINAL for r in cls.robots),
                         'both missions to end (states %s)' % [r.state for r in cls.robots],
                         MISSION_TIMEOUT)
        rospy.sleep(2.0)        # the statuses published after the end (sim time)

    @classmethod
    def _on_tf(cls, msg):
        cls.frames.update((t.header.frame_id, t.child_frame_id) for t in msg.transforms)

    @classmethod
    def _on_diagnostics(cls, msg):
        with cls.lock:
            caller = msg._connection_header['callerid']
            cls.publishers[caller] = max(cls.publishers.get(caller, 0), len(msg.status))
            for status in msg.status:
                if status.message != STARTING:
                    cls.statuses.setdefault(status.name, []).append(status)

    def named(self, robot, role, what):
        name = robot.status_name(role, what)
        with self.lock:
            found = list(self.statuses.get(name, []))
        self.assertTrue(found, 'no status %r on /diagnostics (got %s)' % (name, sorted(self.statuses)))
        return found

    @staticmethod
    def values(status):
        return {kv.key: kv.value for kv in status.values}

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

    def test_5_every_expected_status_arrives_and_the_mission_status_follows_the_state(self):
        for robot in self.robots:
            for role, what in EXPECTED:
                self.named(robot, role, what)
            states = [self.values(s).get('state') for s in self.named(robot, 'back_travel_client', 'mission')]
            for state in ('recording', 'rotating', 'returning', 'home'):
                self.assertIn(state, states, robot.namespace)
            self.assertEqual(states[-1], 'home', robot.namespace)

    def test_6_odometry_age_and_the_landmark_file_size(self):
        for robot in self.robots:
            ages = [float(self.values(s)['age (s)']) for s in self.named(robot, 'back_travel_client', 'odometry')
                    if 'age (s)' in self.values(s)]
            self.assertTrue(ages, '%s: odometry status without an age' % robot.namespace)
            sizes = [int(self.values(s)['bytes']) for s in self.named(robot, 'back_travel_client', 'landmark file')
                     if 'bytes' in self.values(s)]
            self.assertTrue(sizes and max(sizes) > 0, '%s: landmark file status never gave a size: %s'
                            % (robot.namespace, sizes))

    def test_7_visual_odometry_fresh_and_no_calibration_warned(self):
        for robot in self.robots:
            vo = self.named(robot, 'heading_correction', 'heading correction: visual odometry')
            self.assertIn(DiagnosticStatus.OK, [s.level for s in vo])
            self.assertTrue(any('age (s)' in self.values(s) for s in vo), 'no visual-odometry age')
            calibration = self.named(robot, 'heading_correction', 'heading correction: gyro calibration')
            self.assertEqual({s.level for s in calibration}, {DiagnosticStatus.WARN},
                             [s.message for s in calibration][:3])
            self.assertIn('calibrate_gyro', calibration[-1].message)

    def test_8_every_layer_node_publishes_diagnostics(self):
        for robot in self.robots:
            nodes = {'/%s/%s' % (robot.namespace, node) for node in robot.layer_nodes}
            self.assertTrue(nodes <= set(self.publishers), 'silent: %s' % sorted(nodes - set(self.publishers)))

    def test_9_no_error_on_a_healthy_mission(self):
        with self.lock:
            errors = {name: s.message for name, found in self.statuses.items() for s in found
                      if s.level == DiagnosticStatus.ERROR}
        self.assertEqual(errors, {})


if __name__ == '__main__':
    rospy.init_node('two_robots_test')
    rostest.rosrun('blind_navigation', 'two_robots', TwoRobotsTest)

#!/usr/bin/env python3
"""rostest (diagnostics.test, diagnostics_paper.test): during a healthy mission on the fake
TurtleBot, /diagnostics carries the layer's statuses, named after their nodes: the
mission (with its state), odometry (its age), the landmark file (its size), visual
odometry and the gyro calibration (heading correction) and the vision monitor; every
node of the layer publishes on /diagnostics, and no status is an ERROR.

Params: ~namespace (the robot's, '' for the root), ~one_process (the layout)."""
import threading
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_msgs.msg import String

from blind_navigation import names
from blind_navigation.core.mission_state import TERMINAL

import waiting

#: diagnostic_updater's placeholder when a status is added, before its first check ran
STARTING = 'Node starting up'
#: s of wall time for the mission (about 100 s of sim time, at rtf 4 in the .test files)
MISSION_TIMEOUT = 200.0
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


class DiagnosticsTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        ns = rospy.get_param('~namespace', '')
        cls.prefix = '%s/' % ns if ns else ''
        one_process = rospy.get_param('~one_process')
        cls.node_of = {role: 'blind_navigation' if one_process else node for role, node in PAPER_NODES.items()}
        cls.layer_nodes = ['blind_navigation'] if one_process else PAPER_LAYOUT
        cls.lock = threading.Lock()
        cls.statuses = {}       # status name -> [DiagnosticStatus, ...] in arrival order
        cls.publishers = {}     # callerid -> the most statuses in one of its arrays
        cls.state = None
        rospy.Subscriber('/diagnostics', DiagnosticArray, cls._on_diagnostics, queue_size=100)
        rospy.Subscriber('/' + cls.prefix + names.STATE, String, cls._on_state)
        waiting.wait_for(lambda: cls.state in TERMINAL, 'the mission to end (state %s)' % cls.state,
                         MISSION_TIMEOUT)
        rospy.sleep(2.0)        # the statuses published after the end (sim time)

    @classmethod
    def _on_diagnostics(cls, msg):
        with cls.lock:
            caller = msg._connection_header['callerid']
            cls.publishers[caller] = max(cls.publishers.get(caller, 0), len(msg.status))
            for status in msg.status:
                if status.message != STARTING:
                    cls.statuses.setdefault(status.name, []).append(status)

    @classmethod
    def _on_state(cls, msg):
        cls.state = msg.data

    def named(self, role, what):
        name = '%s%s: %s' % (self.prefix, self.node_of[role], what)
        with self.lock:
            found = list(self.statuses.get(name, []))
        self.assertTrue(found, 'no status %r on /diagnostics (got %s)' % (name, sorted(self.statuses)))
        return found

    @staticmethod
    def values(status):
        return {kv.key: kv.value for kv in status.values}

    def test_1_the_mission_came_home(self):
        self.assertEqual(self.state, 'home')

    def test_2_every_expected_status_arrives(self):
        for role, what in EXPECTED:
            self.named(role, what)

    def test_3_the_mission_status_follows_the_state(self):
        states = [self.values(s).get('state') for s in self.named('back_travel_client', 'mission')]
        for state in ('recording', 'rotating', 'returning', 'home'):
            self.assertIn(state, states)
        self.assertEqual(states[-1], 'home')

    def test_4_odometry_age_and_the_landmark_file_size(self):
        ages = [float(self.values(s)['age (s)']) for s in self.named('back_travel_client', 'odometry')
                if 'age (s)' in self.values(s)]
        self.assertTrue(ages, 'odometry status without an age')
        sizes = [int(self.values(s)['bytes']) for s in self.named('back_travel_client', 'landmark file')
                 if 'bytes' in self.values(s)]
        self.assertTrue(sizes and max(sizes) > 0, 'landmark file status never gave a size: %s' % sizes)

    def test_5_visual_odometry_fresh_and_no_calibration_warned(self):
        vo = self.named('heading_correction', 'heading correction: visual odometry')
        self.assertIn(DiagnosticStatus.OK, [s.level for s in vo])
        self.assertTrue(any('age (s)' in self.values(s) for s in vo), 'no visual-odometry age')
        calibration = self.named('heading_correction', 'heading correction: gyro calibration')
        self.assertEqual({s.level for s in calibration}, {DiagnosticStatus.WARN},
                         [s.message for s in calibration][:3])
        self.assertIn('calibrate_gyro', calibration[-1].message)

    def test_6_every_layer_node_publishes_diagnostics(self):
        nodes = {'/%s%s' % (self.prefix, node) for node in self.layer_nodes}
        self.assertTrue(nodes <= set(self.publishers), 'silent: %s' % sorted(nodes - set(self.publishers)))
        empty = sorted(node for node in nodes if not self.publishers[node])
        if empty:
            rospy.logwarn('diagnostics test: layer nodes publishing empty status arrays: %s', empty)

    def test_7_no_error_on_a_healthy_mission(self):
        with self.lock:
            errors = {name: s.message for name, found in self.statuses.items() for s in found
                      if s.level == DiagnosticStatus.ERROR}
        self.assertEqual(errors, {})


if __name__ == '__main__':
    rospy.init_node('diagnostics_test')
    rostest.rosrun('blind_navigation', 'diagnostics', DiagnosticsTest)

#!/usr/bin/env python3
"""rostest (gyro_calibration.test): calibrate_gyro on the fake TurtleBot (paper noise profile).

``/calibrate_gyro``: an older calibration file is in place; the node spins, writes the new
calibration (the old one kept as ``.previous``) and exits; the measured scale error is the
profile's within 4 standard errors, known to better than 0.002; the robot stands still.

``/calibrate_gyro_no_vo``, beside it: its visual odometry (remapped to ``~no_vo_topic``)
carries only RTAB-Map's lost messages, published here; it never drives (nothing but zero on
its own mux input, remapped to ``~no_vo_cmd_vel``), logs the failure naming visual odometry
as an error after its start_timeout and exits without writing a file.
"""
import os
import threading
import time
import unittest
from xmlrpc.client import ServerProxy

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log

from blind_navigation.core.gyro_calibration import GyroCalibration, load_calibration, save_calibration
from blind_navigation.sim.kobuki import load_profile

from waiting import wait_for

NODE, NO_VO_NODE = '/calibrate_gyro', '/calibrate_gyro_no_vo'
#: Sim seconds the spins take at most: 2 x 5 turns at 0.6 rad/s (105 s) + 3 pauses of 3 s + slack.
SIM_BUDGET = 125.0
#: Old calibration put in place before the run.
OLD = GyroCalibration(0.0123, 0.001, 0.0, 0.0001, 40)
STILL = 0.005   # m/s and rad/s: ground-truth speeds below this count as standing still
#: s (wall) the node without visual odometry may take to give up: its start_timeout + slack
NO_VO_WALL = 20.0
LOST_DIAGONAL = [9999.0 if i % 7 == 0 else 0.0 for i in range(36)]


def node_uri(name):
    """The node's XML-RPC URI while registered with the master, else None."""
    try:
        return rosgraph.Master(rospy.get_name()).lookupNode(name)
    except rosgraph.MasterError:
        return None


def process_alive(uri):
    """Whether the node's XML-RPC server still answers (the master keeps an exited node's
    registrations, so only the process itself tells that it is gone)."""
    try:
        ServerProxy(uri).getPid(rospy.get_name())
        return True
    except OSError:
        return False


def lost_odometry():
    """RTAB-Map's visual odometry when lost: null pose, covariance 9999."""
    msg = Odometry()
    msg.header.stamp = rospy.Time.now()
    msg.pose.covariance = msg.twist.covariance = LOST_DIAGONAL
    return msg


class GyroCalibrationTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.path = rospy.get_param('~calibration_file')
        cls.no_vo_path = rospy.get_param('~no_vo_calibration_file')
        rtf = float(rospy.get_param('~rtf'))
        # wall budget: the fake may run 3x slower than rtf on a loaded machine
        cls.timeout = SIM_BUDGET / rtf * 3.0 + 15.0
        for stale in (cls.path, cls.path + '.previous', cls.path + '.tmp', cls.no_vo_path,
                      cls.no_vo_path + '.tmp'):
            if os.path.exists(stale):
                os.remove(stale)
        save_calibration(cls.path, OLD, 1.0)
        cls.lock = threading.Lock()
        cls.errors = {NODE: [], NO_VO_NODE: []}
        cls.truth, cls.no_vo_commands = [], []
        rospy.Subscriber('/rosout', Log, cls._on_log, queue_size=100)
        rospy.Subscriber('/ground_truth/odom', Odometry, cls.truth.append, queue_size=100)
        rospy.Subscriber(rospy.get_param('~no_vo_cmd_vel'), Twist, cls.no_vo_commands.append)
        lost = rospy.Publisher(rospy.get_param('~no_vo_topic'), Odometry, queue_size=5)
        cls.stop_lost = threading.Event()
        threading.Thread(target=cls._publish_lost, args=(lost,), daemon=True).start()
        cls.uris = {}
        for name in (NODE, NO_VO_NODE):
            wait_for(lambda: node_uri(name), 'waiting for %s to register with the master' % name, 20.0)
            cls.uris[name] = node_uri(name)

    @classmethod
    def tearDownClass(cls):
        cls.stop_lost.set()

    @classmethod
    def _publish_lost(cls, publisher):
        while not cls.stop_lost.wait(0.05) and not rospy.is_shutdown():
            publisher.publish(lost_odometry())

    @classmethod
    def _on_log(cls, msg):
        name = '/' + msg.name.lstrip('/')
        if name in cls.errors and msg.level >= Log.ERROR:
            with cls.lock:
                cls.errors[name].append(msg.msg)

    def node_errors(self, name):
        with self.lock:
            return list(self.errors[name])

    def wait_until_finished(self, name, timeout):
        started = time.monotonic()
        wait_for(lambda: not process_alive(self.uris[name]), 'waiting for %s to exit (%.0f s wall)'
                 % (name, timeout), timeout)
        rospy.loginfo('%s exited after %.1f s (wall)', name, time.monotonic() - started)

    def assert_still(self):
        """Ground truth of the last 0.5 s, 1 s (sim) after the node exited: not moving."""
        end = rospy.Time.now().to_sec() + 1.5
        wait_for(lambda: self.truth and self.truth[-1].header.stamp.to_sec() > end,
                 'waiting for 1.5 s of ground truth after the node exited', 20.0)
        recent = [m.twist.twist for m in self.truth if m.header.stamp.to_sec() > end - 0.5]
        fastest = max(max(abs(t.linear.x), abs(t.angular.z)) for t in recent)
        self.assertLess(fastest, STILL, 'robot still moving after calibrate_gyro exited: '
                        '%.4f m/s or rad/s on /ground_truth/odom' % fastest)

    def test_calibration(self):
        self.wait_until_finished(NODE, self.timeout)
        self.assertTrue(os.path.exists(self.path), 'no calibration written to %s; node errors: %s'
                        % (self.path, self.node_errors(NODE)))
        self.assertEqual(load_calibration(self.path + '.previous'), OLD,
                         'the earlier calibration was not kept as .previous')
        result = load_calibration(self.path)
        expected = load_profile('paper')['gyro_scale_error']
        rospy.loginfo('measured %s; profile scale error %+.5f', result.describe(), expected)
        self.assertLess(result.scale_std, 0.002, result.describe())
        self.assertLess(abs(result.scale - expected), 4 * result.scale_std + 1e-4,
                        '%s vs the profile scale error %+.5f' % (result.describe(), expected))
        self.assertEqual(self.node_errors(NODE), [], 'calibrate_gyro logged errors on success')
        self.assert_still()

    def test_without_visual_odometry_it_never_spins(self):
        self.wait_until_finished(NO_VO_NODE, NO_VO_WALL)
        self.assertFalse(os.path.exists(self.no_vo_path), 'a calibration was written despite lost vision')
        self.assertFalse(os.path.exists(self.no_vo_path + '.tmp'), 'a partial calibration file was left')
        wait_for(lambda: any('FAILED' in e for e in self.node_errors(NO_VO_NODE)),
                 'waiting for %s\'s failure on /rosout (errors seen: %s)'
                 % (NO_VO_NODE, self.node_errors(NO_VO_NODE)), 5.0)
        self.assertTrue(any('visual odometry' in e for e in self.node_errors(NO_VO_NODE)),
                        'the failure does not name visual odometry: %s' % self.node_errors(NO_VO_NODE))
        moving = [t for t in self.no_vo_commands if t.linear.x or t.angular.z]
        self.assertEqual(moving, [], '%s commanded motion without visual odometry' % NO_VO_NODE)


if __name__ == '__main__':
    rospy.init_node('test_gyro_calibration')
    rostest.rosrun('blind_navigation', 'test_gyro_calibration', GyroCalibrationTest)

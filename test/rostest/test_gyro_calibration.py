#!/usr/bin/env python3
"""rostest: calibrate_gyro on the fake TurtleBot (paper noise profile).

``~expect: success`` (gyro_calibration.test): an older calibration file is in
place; the node spins, writes the new calibration (the old one kept as
``.previous``) and exits; the measured scale error is the profile's within
4 standard errors, known to better than 0.002; the robot stands still.
``~expect: failure`` (gyro_calibration_vision_lost.test): visual odometry is
lost before the node starts; the node does not spin, logs the failure (naming
visual odometry) as an error and exits without writing a file; the robot stands
still.
"""
import os
import time
import unittest
from xmlrpc.client import ServerProxy

import rosgraph
import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log

from blind_navigation.core.gyro_calibration import GyroCalibration, load_calibration, save_calibration
from blind_navigation.sim.kobuki import load_profile

from waiting import wait_for

NODE = '/calibrate_gyro'
#: Sim seconds the spins take at most: 2 x 5 turns at 0.6 rad/s (105 s) + 3 pauses of 3 s + slack.
SIM_BUDGET = 125.0
#: Old calibration put in place before the run (success case).
OLD = GyroCalibration(0.0123, 0.001, 0.0, 0.0001, 40)
STILL = 0.005   # m/s and rad/s: ground-truth speeds below this count as standing still


def node_uri():
    """The node's XML-RPC URI while registered with the master, else None."""
    try:
        return rosgraph.Master(rospy.get_name()).lookupNode(NODE)
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


class GyroCalibrationTest(unittest.TestCase):

    def setUp(self):
        self.expect = rospy.get_param('~expect')
        self.path = rospy.get_param('~calibration_file')
        rtf = float(rospy.get_param('~rtf'))
        # wall budget: the fake may run 3x slower than rtf on a loaded machine
        self.timeout = SIM_BUDGET / rtf * 3.0 + 15.0
        for stale in (self.path, self.path + '.previous', self.path + '.tmp'):
            if os.path.exists(stale):
                os.remove(stale)
        if self.expect == 'success':
            save_calibration(self.path, OLD, 1.0)
        self.errors, self.truth = [], []
        rospy.Subscriber('/rosout', Log, self._on_log, queue_size=100)
        rospy.Subscriber('/ground_truth/odom', Odometry, self.truth.append, queue_size=100)
        wait_for(node_uri, 'waiting for %s to register with the master' % NODE, 20.0)
        self.uri = node_uri()

    def _on_log(self, msg):
        if msg.name == NODE and msg.level >= Log.ERROR:
            self.errors.append(msg.msg)

    def wait_until_finished(self):
        started = time.monotonic()
        wait_for(lambda: not process_alive(self.uri), 'waiting for %s to finish the spins and exit (%.0f s sim '
                 'budget)' % (NODE, SIM_BUDGET), self.timeout)
        rospy.loginfo('%s exited after %.1f s (wall)', NODE, time.monotonic() - started)

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
        self.wait_until_finished()
        if self.expect == 'success':
            self.assertTrue(os.path.exists(self.path), 'no calibration written to %s; node errors: %s'
                            % (self.path, self.errors))
            self.assertEqual(load_calibration(self.path + '.previous'), OLD,
                             'the earlier calibration was not kept as .previous')
            result = load_calibration(self.path)
            expected = load_profile('paper')['gyro_scale_error']
            rospy.loginfo('measured %s; profile scale error %+.5f', result.describe(), expected)
            self.assertLess(result.scale_std, 0.002, result.describe())
            self.assertLess(abs(result.scale - expected), 4 * result.scale_std + 1e-4,
                            '%s vs the profile scale error %+.5f' % (result.describe(), expected))
            self.assertEqual(self.errors, [], 'calibrate_gyro logged errors on success')
        else:
            self.assertFalse(os.path.exists(self.path), 'a calibration was written despite lost vision')
            self.assertFalse(os.path.exists(self.path + '.tmp'), 'a partial calibration file was left')
            wait_for(lambda: any('FAILED' in e for e in self.errors),
                     'waiting for calibrate_gyro\'s failure on /rosout (errors seen: %s)' % self.errors, 5.0)
            self.assertTrue(any('visual odometry' in e for e in self.errors),
                            'the failure does not name visual odometry: %s' % self.errors)
        self.assert_still()


if __name__ == '__main__':
    rospy.init_node('test_gyro_calibration')
    rostest.rosrun('blind_navigation', 'test_gyro_calibration', GyroCalibrationTest)

#!/usr/bin/env python3
"""rostest: vision lost on the fake with its dock behind the start, dock_at_home: the robot
turns, returns and docks (mission_docking.test).

The states walk idle, recording, rotating, returning, docking, docked; the status names the
charger, outcome DOCKED; the fake's SensorState reports charging (6) once docked and the robot stands on
the dock (ground truth: stopped, where the dock's contacts are).
"""
import math
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import STOPPED_SPEED, MissionRun  # noqa: E402
from recording_tools import Collector  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.geometry import Pose2D  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402
from blind_navigation.ros import kobuki_msgs_compat as kobuki  # noqa: E402
from blind_navigation.sim.dock import CHARGING, Dock  # noqa: E402

DOCK_WALK = ['idle', 'recording', 'rotating', 'returning', 'docking', 'docked']
#: m the robot's centre may be from the docked pose: the dock's contacts meet within 0.05 m
#: of its axis (sim/dock.CONTACT_HALF_WIDTH) and 0.005 m of its face
ON_THE_DOCK = 0.06


class DockingTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission_run = run = MissionRun(float(rospy.get_param('~wall_timeout', 200.0)))
        cls.core = Collector(names.CORE_SENSORS, kobuki.SensorState)
        try:
            run.record_mission(rospy.get_param('~mission'))
            run.trigger_by_publisher()
            run.wait_until_final()
            run.wait(lambda: cls.core.snapshot() and cls.core.snapshot()[-1].charger == CHARGING,
                     'the fake never reported charging (charger %d) after %s' % (
                         CHARGING, run.state_names()))
        finally:
            run.stop_operator()

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()

    def test_the_return_ends_docked_on_the_charger(self):
        run = self.mission_run
        status = run.status.snapshot()[-1]
        x, y = run.truth.position()
        docked = Dock.behind(Pose2D(0.0, 0.0, 0.0)).docked_pose()      # the fake's world: start at 0
        rospy.loginfo('DOCKING: %s; %s; the robot %.3f m from the docked pose, charger %d',
                      run.state_names(), status.reason, math.hypot(x - docked.x, y - docked.y),
                      self.core.snapshot()[-1].charger)
        self.assertEqual(run.state_names(), DOCK_WALK)
        self.assertIn('docked on the charger', status.reason)
        self.assertEqual(status.outcome, MissionStatus.OUTCOME_DOCKED)
        self.assertLess(math.hypot(x - docked.x, y - docked.y), ON_THE_DOCK)
        self.assertLess(run.truth.speed(), STOPPED_SPEED)


if __name__ == '__main__':
    rospy.init_node('test_mission_docking')
    rostest.rosrun('blind_navigation', 'mission_docking', DockingTest)

#!/usr/bin/env python3
"""rostest: a low battery brings the robot home (mission_battery.test), two cases in one run.

The fake's noisy battery drains through ``battery_low``: the test starts the operator once
the battery reads ``go_above`` V above the threshold (median of :data:`LEVEL_READINGS`), so the
recording ends above it; then the robot stands recording while the battery drains.
``test_noisy_readings_above_the_threshold_start_nothing``: readings below the threshold
came while the battery (the mean of the readings around) was above it, and no return
started. ``test_the_battery_below_the_threshold_brings_the_robot_home``: the return started
only once the battery was below, the reason naming the voltage and the threshold, and the
robot came home (ground truth) within 2 % of the recorded path.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import HOME_WALK, MissionRun  # noqa: E402
from recording_tools import Collector  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402
from blind_navigation.ros import kobuki_msgs_compat as kobuki  # noqa: E402

MAX_RELATIVE_ERROR = 0.02
#: readings (10 Hz) in the median that tells the test the battery's level before it starts
LEVEL_READINGS = 21
#: s of readings either side of a moment whose mean stands for the battery's true level
#: (0.1 V std noise: the mean of 50 readings is within 0.05 V)
TRUTH_SPAN = 2.5
#: noisy readings below the threshold the first case must have seen (else it proves nothing)
MIN_DIPS = 10


def median(values):
    return sorted(values)[len(values) // 2]


class BatteryTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission_run = run = MissionRun(float(rospy.get_param('~wall_timeout', 240.0)))
        cls.threshold = run.param('mission_owner', 'battery_low')
        cls.status = Collector(names.STATUS, MissionStatus)
        cls.core = Collector(names.CORE_SENSORS, kobuki.SensorState)
        go_at = cls.threshold + float(rospy.get_param('~go_above'))
        try:
            run.wait_for_layer()
            run.wait(lambda: len(cls.core) >= LEVEL_READINGS and median(
                [v for _, v in cls.readings()[-LEVEL_READINGS:]]) <= go_at,
                'the battery never read %.1f V (fake battery_drain?)' % go_at)
            run.start_operator(rospy.get_param('~mission'))
            cls.at_operator_done = run.wait_for_operator(rospy.get_param('~mission'))
            cls.outcome = run.outcome()
        finally:
            run.stop_operator()

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()

    @classmethod
    def readings(cls):
        """[(sim time, V)] of every battery reading."""
        with cls.core._lock:
            return [(t, msg.battery / 10.0) for t, msg in cls.core.items]

    def level(self, t):
        """The battery's level at sim time ``t``: the mean of the readings around it."""
        near = [v for s, v in self.readings() if abs(s - t) <= TRUTH_SPAN]
        self.assertGreater(len(near), 20, 'too few battery readings around t %.1f s' % t)
        return sum(near) / len(near)

    def triggered_at(self):
        """(sim time, reason) of the status that started the return."""
        with self.status._lock:
            rotating = [(t, msg.reason) for t, msg in self.status.items if msg.state == 'rotating']
        self.assertTrue(rotating, 'no return started; states %s' % self.mission_run.state_names())
        return rotating[0]

    def test_noisy_readings_above_the_threshold_start_nothing(self):
        self.assertEqual(self.at_operator_done[-1:], ['recording'], 'the return started while driving')
        trigger = self.triggered_at()[0]
        readings = self.readings()
        first = readings[0][0] + TRUTH_SPAN     # a level needs the readings on both sides
        above = [(t, v) for t, v in readings
                 if first <= t < trigger - TRUTH_SPAN and self.level(t) >= self.threshold]
        dips = [v for _, v in above if v < self.threshold]
        rospy.loginfo('BATTERY: %d of %d readings below %.1f V while the battery was above it, '
                      'nothing started', len(dips), len(above), self.threshold)
        self.assertGreaterEqual(len(dips), MIN_DIPS, 'the noise never reached below the threshold')

    def test_the_battery_below_the_threshold_brings_the_robot_home(self):
        trigger, reason = self.triggered_at()
        level = self.level(trigger - TRUTH_SPAN)
        rospy.loginfo('BATTERY: return at t %.1f s (%s); the battery %.2f V before it; home %.4f m '
                      'from the start on a %.2f m path', trigger, reason, level, self.outcome.error,
                      self.outcome.loaded.total_distance)
        self.assertLess(level, self.threshold, 'the return started above the threshold')
        self.assertTrue(reason.startswith('battery low: ') and
                        'below battery_low %.1f V' % self.threshold in reason, reason)
        named = float(reason.split('battery low: ')[1].split(' V')[0])
        self.assertLess(named, self.threshold)
        self.assertEqual(self.mission_run.state_names(), HOME_WALK)
        self.assertLess(self.outcome.error, MAX_RELATIVE_ERROR * self.outcome.loaded.total_distance)


if __name__ == '__main__':
    rospy.init_node('test_mission_battery')
    rostest.rosrun('blind_navigation', 'mission_battery', BatteryTest)

#!/usr/bin/env python3
"""rostest: the two-rate sampling follows the path (paper section 3.3.2) on the fake
TurtleBot with the paper noise profile and the default dead-band.

The mission is a long straight, a quarter-turn arc at the paper's set velocities and
a long straight. Each tick's period is the cycle that just ended, decided from the
four yaws before it, so a change of segment shows at most DETECTION_LAG after it.
Checked: straight period on the straights, curved period on the arc, the same
periods in the file, and no other period but the final partial cycle's. This node
is the sampling publisher's ~mission_owner: it ends the recording by moving the
mission state to rotating (vision lost).
"""
import os
import shutil
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from recording_tools import Collector, wait_for  # noqa: E402

from blind_navigation import names
from blind_navigation.sim.mission import load_mission  # noqa: E402
from blind_navigation.core.store import load_landmarks  # noqa: E402
from blind_navigation.msg import PathSample  # noqa: E402
from mission_owner import MissionOwner  # noqa: E402

STRAIGHT_T, CURVED_T = 2.0, 1.0
#: Four yaws (three straight cycles) to see a change, one more cycle to act on it.
DETECTION_LAG = 3 * STRAIGHT_T + STRAIGHT_T
MISSION_WALL_TIMEOUT = 120.0    # s wall (the mission is ~75 s of sim time at rtf 10)


class RecordingCurvesTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission = load_mission(rospy.get_param('~mission'))
        cls.arc_w = max(abs(w) for _, w, _ in cls.mission.segments)
        cls.landmark_file = rospy.get_param('~landmark_file')
        cls.samples = Collector(names.SAMPLE, PathSample)
        cls.operator_start, cls.turning = [], []
        # the base's stamped odometry, not the receipt time of a command: under load a
        # message reaches this node late, and at rtf 10 each wall ms is 10 ms of sim time
        rospy.Subscriber('/odom', Odometry, cls.on_odom, queue_size=200)
        done = Collector('/mission_driver/done', Bool)
        owner = MissionOwner('/sampling_publisher')
        owner.publish('recording')
        wait_for(lambda: any(msg.data for msg in done.snapshot()), 'the mission never finished',
                 timeout=MISSION_WALL_TIMEOUT)
        rotating_at = rospy.get_time()
        owner.publish('rotating')    # vision lost: the mission's owner ends the recording
        wait_for(lambda: cls.recording_stopped(rotating_at),
                 'the recording did not stop after the mission moved to rotating')
        cls.ticks = [s for s in cls.samples.snapshot() if s.command == 'sample']
        wait_for(lambda: cls.saved() >= len(cls.ticks), 'the saver did not save every tick')
        cls.loaded = load_landmarks(cls.landmark_file)
        # the arc as the base drove it (under load the operator's first command can reach
        # the base late, and its timed segments then end early against the base's start)
        assert cls.turning, 'the base never turned'
        cls.arc = (cls.turning[0] - cls.operator_start[0], cls.turning[-1] - cls.operator_start[0])

    @classmethod
    def recording_stopped(cls, rotating_at):
        """A final sample, or none when the state came at a tick (no time since it: the
        publisher logs so) and no tick followed for two straight periods."""
        samples = cls.samples.snapshot()
        return any(s.command == 'final' for s in samples) or (
            rospy.get_time() > rotating_at + 2 * STRAIGHT_T and samples
            and samples[-1].header.stamp.to_sec() <= rotating_at + 0.1)

    @classmethod
    def on_odom(cls, msg):
        if not cls.operator_start and abs(msg.twist.twist.linear.x) > 1e-3:  # it starts straight
            cls.operator_start.append(msg.header.stamp.to_sec())
        if cls.operator_start and abs(msg.twist.twist.angular.z) > cls.arc_w / 2:
            cls.turning.append(msg.header.stamp.to_sec())

    @classmethod
    def saved(cls):
        try:
            return len(load_landmarks(cls.landmark_file, allow_empty=True).landmarks)
        except Exception:           # not created yet
            return 0

    @classmethod
    def tearDownClass(cls):
        directory = os.path.dirname(cls.landmark_file)
        if directory.endswith('-recording-test'):       # only the launch's private directory
            shutil.rmtree(directory, ignore_errors=True)

    def mission_time(self, sample):
        self.assertTrue(self.operator_start, 'the operator never drove')
        return sample.header.stamp.to_sec() - self.operator_start[0]

    def periods_between(self, start, end):
        return [(round(self.mission_time(s), 1), s.period) for s in self.ticks
                if start < self.mission_time(s) <= end]

    def test_straight_period_before_the_arc(self):
        before = self.periods_between(-1e9, self.arc[0])
        self.assertGreaterEqual(len(before), 5, before)
        self.assertTrue(all(period == STRAIGHT_T for _, period in before), before)

    def test_curved_period_on_the_arc(self):
        on_arc = self.periods_between(self.arc[0] + DETECTION_LAG, self.arc[1])
        self.assertGreaterEqual(len(on_arc), 5, on_arc)
        self.assertTrue(all(period == CURVED_T for _, period in on_arc), on_arc)

    def test_straight_period_again_after_the_arc(self):
        after = self.periods_between(self.arc[1] + DETECTION_LAG, 1e9)
        self.assertGreaterEqual(len(after), 5, after)
        self.assertTrue(all(period == STRAIGHT_T for _, period in after), after)

    def test_file_holds_the_published_periods(self):
        periods = [landmark.T for landmark in self.loaded.landmarks]
        self.assertEqual(periods[:len(self.ticks)], [s.period for s in self.ticks])
        self.assertTrue(set(periods[:-1]) <= {STRAIGHT_T, CURVED_T}, sorted(set(periods)))


if __name__ == '__main__':
    rospy.init_node('test_recording_curves')
    rostest.rosrun('blind_navigation', 'recording_curves', RecordingCurvesTest)

#!/usr/bin/env python3
"""rostest: one whole mission on the fake TurtleBot (mission_*.test).

The layer (blind_navigation.launch) records while the fake's scripted operator
plays ``~mission`` (``~operator``: ``test`` = started by this node once the
layer records; ``launch`` = the fake's own, started by the launch with a
``start_delay``); then vision is lost, by ``~trigger``:

- ``rostopic``: `rostopic pub -1 /blind_navigation/vision_lost std_msgs/Empty "{}"`
  run as a subprocess, as in the paper's experiments;
- ``publisher``: the same message published by this node;
- ``auto``: the fake's camera fails (``vision_fail_at``) and vision_monitor
  detects it (its latched ~loss names a detector other than ``manual``).

Asserted: the state walks idle -> recording -> rotating -> returning -> home;
the goals sent are the recorder's (``~recorder`` variant) landmarks in reverse
order (in the heading correction's frame), every one of them (owner:=mission,
which has no action: its final status counts them); the robot ends within ``~max_error`` m of its start
on /ground_truth/odom and stands still there; RViz's latched paths, the heading correction and the
return's progress file (home, every landmark) are there as a user finds them after the mission.
"""
import os
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Path
from std_msgs.msg import String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import PSI_TOLERANCE, HomeMission, STOPPED_SPEED, MissionRun  # noqa: E402
from recording_tools import Collector  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.geometry import wrap_angle  # noqa: E402
from blind_navigation.core.progress import load_progress, progress_path  # noqa: E402
from blind_navigation.msg import HeadingCorrection  # noqa: E402
from blind_navigation.sim.mission import load_mission  # noqa: E402


class MissionTest(HomeMission, unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission = rospy.get_param('~mission')
        cls.trigger = rospy.get_param('~trigger')
        cls.recorder = rospy.get_param('~recorder')
        operator = rospy.get_param('~operator', 'test')
        triggers = {'rostopic': MissionRun.trigger_by_rostopic,
                    'publisher': MissionRun.trigger_by_publisher, 'auto': None}
        if cls.trigger not in triggers or operator not in ('test', 'launch'):
            raise ValueError('~trigger must be one of %s and ~operator test or launch, got %r, %r'
                             % (', '.join(triggers), cls.trigger, operator))
        cls.max_error = float(rospy.get_param('~max_error'))
        cls.mission_run = MissionRun(float(rospy.get_param('~wall_timeout', 240.0)))
        cls.loss = Collector(cls.mission_run.loss_topic, String)
        try:
            cls.mission_run.wait_for_layer()
            if operator == 'test':
                cls.mission_run.start_operator(cls.mission)
            cls.states_at_mission_end = cls.mission_run.wait_for_operator(cls.mission)
            if triggers[cls.trigger]:
                triggers[cls.trigger](cls.mission_run)
            cls.error, cls.speed, cls.loaded = cls.mission_run.outcome()
        finally:
            cls.mission_run.stop_operator()
        rospy.loginfo('MISSION %s (%s, %s recorder, %s trigger, %s): state %s, final error %.3f m '
                      '(limit %.3f m), %d landmarks, %.2f m recorded, speed %.4f m/s',
                      cls.mission, cls.mission_run.param('back_travel_server', 'control'), cls.recorder,
                      cls.trigger, 'one process' if cls.mission_run.compact else 'paper layout',
                      cls.mission_run.state_names()[-1], cls.error, cls.max_error,
                      len(cls.loaded.landmarks), cls.loaded.total_distance, cls.speed)

    def test_the_whole_mission_was_recorded_before_vision_was_lost(self):
        # Recording began with the robot at its start (the fake's ground truth
        # starts at the origin), and vision was lost after the operator was done
        # (the operator and the back travel both drive the teleop input).
        self.assertLess(abs(self.mission_run.start[0]) + abs(self.mission_run.start[1]), 0.001,
                        'the robot had moved before the recording started')
        self.assertEqual(self.states_at_mission_end, ['idle', 'recording'])
        if self.trigger == 'auto':
            losses = [msg.data for msg in self.loss.snapshot()]
            self.assertTrue(losses, 'vision_monitor published no ~loss')
            self.assertFalse(losses[0].startswith('manual'), losses[0])

    def test_every_recorded_landmark_is_driven_back_in_reverse(self):
        self.assertEqual(self.loaded.metadata.get('recorder'), self.recorder)
        if self.mission_run.mission_object():
            # owner:=mission drives the goals inside the mission object: no BackTravel action
            # to watch; the status counts the landmarks the return drove back
            status = self.mission_run.status.snapshot()[-1]
            self.assertEqual((status.state, status.landmarks, status.completed),
                             ('home', len(self.loaded.landmarks), len(self.loaded.landmarks)))
            return
        # One succeeded result per landmark: each one was sent and driven...
        self.assert_every_landmark_succeeded(5)
        # ... in reverse order, as recorded (in the heading correction's frame; the goals
        # seen: at least the moving ones).
        expected = self.mission_run.goals_expected(self.loaded.landmarks)
        seen = self.mission_run.goal_values()
        moving = sum(1 for landmark in self.loaded.landmarks if landmark.d > 0)
        self.assertGreaterEqual(len(seen), moving)
        expected = expected[len(expected) - len(seen):]
        self.assertEqual([goal[:4] for goal in seen], [goal[:4] for goal in expected])
        far = [(got[4], want[4]) for got, want in zip(seen, expected)
               if abs(wrap_angle(got[4] - want[4])) > PSI_TOLERANCE]
        self.assertEqual(far, [], 'goal headings differ from the recorded ones in the '
                         'correction\'s frame by more than %g rad' % PSI_TOLERANCE)

    def test_the_last_landmark_was_taken_before_the_turn(self):
        # rotate_pi waits for the recorder's final sample before turning, so no part of
        # the pi turn (up to 0.6 rad/s) is recorded: the robot is at rest when vision is
        # lost after the operator's last (straight) segment, so |w| is gyro noise and the
        # yaw has not moved since the previous landmark.
        previous, last = self.loaded.landmarks[-2:]
        self.assertLess(abs(last.w), 0.05, 'last landmark %r has a turn rate: the pi turn '
                        'was recorded' % (tuple(last),))
        self.assertLess(abs(wrap_angle(last.psi - previous.psi)), 0.05,
                        'yaw moved %.3f rad in the last landmark' % (last.psi - previous.psi))

    def test_the_operator_drove_the_mission(self):
        # The limits are set for the mission's path: on a machine too loaded for the rtf,
        # the operator's commands lapse (the base's 0.6 s watchdog stops it) and the robot
        # drives another, shorter path. The recorded chord sum is within 1 % of the
        # drive on these paths; the paper profile's speed droop costs up to 4 %.
        nominal = load_mission(self.mission).nominal_length()
        self.assertGreater(self.loaded.total_distance, 0.9 * nominal,
                           'recorded %.2f m of the %.2f m mission: the operator lapsed (rtf too '
                           'high for the machine load?)' % (self.loaded.total_distance, nominal))

    def test_the_paths_the_correction_and_the_progress_are_kept(self):
        latched = {topic: rospy.wait_for_message(topic, msg_type, timeout=10.0)
                   for topic, msg_type in ((names.RECORDED_PATH, Path), (names.RETURN_ROUTE, Path),
                                           (names.RETURN_PATH, Path),
                                           (names.HEADING_CORRECTION, HeadingCorrection))}
        landmarks = len(self.loaded.landmarks)
        # the recording's start and one pose per landmark; the route from where it stopped
        self.assertEqual(len(latched[names.RECORDED_PATH].poses), landmarks + 1)
        self.assertGreater(len(latched[names.RETURN_ROUTE].poses), 1)
        recorded = self.loaded.total_distance
        driven = latched[names.RETURN_PATH].poses
        self.assertGreater(len(driven), recorded / 0.1, 'return_path: a pose every 0.02 m driven')
        self.assertIn(latched[names.HEADING_CORRECTION].status, ('full', 'bias', 'scale', 'none'))
        storage = self.mission_run.storage_msgs.snapshot()[-1]
        progress = load_progress(progress_path(os.path.join(os.path.dirname(storage.file),
                                                            'landmarks.yaml')))
        self.assertEqual((progress.status, progress.landmarks, progress.completed),
                         ('home', landmarks, landmarks))
        self.assertEqual(progress.landmark_file, os.path.realpath(storage.file))

    def test_robot_ends_near_its_start(self):
        self.assertLessEqual(self.error, self.max_error,
                             '%s: ended %.3f m from its start (limit %.3f m)'
                             % (self.mission, self.error, self.max_error))

    def test_robot_stands_still_at_home(self):
        self.assertLess(self.speed, STOPPED_SPEED)


if __name__ == '__main__':
    rospy.init_node('test_mission')
    rostest.rosrun('blind_navigation', 'mission', MissionTest)

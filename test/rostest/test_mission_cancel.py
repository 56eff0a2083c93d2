#!/usr/bin/env python3
"""rostest: cancelling the back travel mid-return stops the robot (mission_cancel.test).

A short mission is recorded on the fake TurtleBot and vision is lost; while the
robot drives back (several goals done, moving at its recorded speed) every
goal is cancelled on /blind_navigation/back_travel/cancel. Asserted: zero
velocity reaches the mux input (teleop) sooner than the base's own 0.6 s
command timeout would stop it, no motion command follows (at most the one a
control cycle already had in flight), the base stops and stays put, the
client sends no further goal and the state ends ``aborted`` with the server's cause, the
goal's BackTravel result ``outcome``: OUTCOME_CANCELLED on the status.
With ``~record_rtf`` the mission is recorded with the fake's clock at that rtf,
the rest (from the vision loss on) at the launch's rtf.
"""
import os
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import STOPPED_SPEED, TELEOP_TOPIC, MissionRun, TimedTwists  # noqa: E402

from blind_navigation.msg import MissionStatus  # noqa: E402

#: m/s on ground truth: the robot is really driving back when the cancel is sent
#: (the return replays about 0.1 m/s).
MOVING_SPEED = 0.05
#: goals already done when cancelling: mid-return, not at its first goal.
GOALS_BEFORE_CANCEL = 4
#: s of sim time: the zero command must come before the fake Kobuki's 0.6 s
#: command timeout (docs/fake_turtlebot.md), else that watchdog, not the cancel,
#: would be what stops the robot.
ZERO_WITHIN = 0.5
#: s of sim time for the base to stop after the cancel (ideal profile: at once),
#: then how long it must stay put, and how little it may move meanwhile (m).
STOP_WITHIN, STAY_FOR, STAY_WITHIN = 1.0, 2.0, 0.002


class CancelTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission_run = run = MissionRun(float(rospy.get_param('~wall_timeout', 240.0)))
        cls.teleop = TimedTwists(TELEOP_TOPIC)
        try:
            run.record_mission(rospy.get_param('~mission'), rospy.get_param('~record_rtf', 0.0))
            cls.landmarks = len(run.recorded().landmarks)
            run.trigger_by_publisher()
            cls.speed_at_cancel, cls.cancelled_at = run.wait_mid_return(GOALS_BEFORE_CANCEL,
                                                                        MOVING_SPEED)
            run.cancel_all_goals()
            cls.goals_at_cancel = len(run.goals.snapshot())
            run.wait(lambda: run.state_names()[-1:] in (['aborted'], ['home']),
                     'the client never ended the return after the cancel; states %s' % run.state_names())
            run.wait_sim(STOP_WITHIN, 'the base stopping')
            cls.stopped_speed = run.truth.speed()
            cls.stopped_at = run.truth.position()
            run.wait_sim(STAY_FOR, 'the base staying put')
            cls.final_at = run.truth.position()
        finally:
            run.stop_operator()
        rospy.loginfo('CANCEL: at %.2f m/s after %d of %d goals; speed %.4f m/s %.1f s later',
                      cls.speed_at_cancel, cls.goals_at_cancel, cls.landmarks, cls.stopped_speed,
                      STOP_WITHIN)

    @classmethod
    def tearDownClass(cls):
        cls.mission_run.remove_recording()

    def test_zero_velocity_on_the_mux_input_at_once(self):
        after = self.teleop.after(self.cancelled_at)
        zeros = [i for i, (_, v, w) in enumerate(after) if v == 0.0 and w == 0.0]
        self.assertTrue(zeros, 'no zero velocity on %s after the cancel' % TELEOP_TOPIC)
        first_zero_at = after[zeros[0]][0]
        rospy.loginfo('CANCEL: first zero on teleop %.3f s (sim) after the cancel',
                      first_zero_at - self.cancelled_at)
        self.assertLessEqual(first_zero_at - self.cancelled_at, ZERO_WITHIN)
        moving = [item for item in after[zeros[0]:] if item[1] or item[2]]
        self.assertLessEqual(len(moving), 1, 'motion commands after the stop: %s' % moving)
        self.assertEqual(after[-1][1:], (0.0, 0.0), 'the last command on teleop is not zero')

    def test_base_stops_and_stays_put(self):
        self.assertGreater(self.speed_at_cancel, MOVING_SPEED)
        self.assertLess(self.stopped_speed, STOPPED_SPEED)
        moved = ((self.final_at[0] - self.stopped_at[0]) ** 2
                 + (self.final_at[1] - self.stopped_at[1]) ** 2) ** 0.5
        self.assertLess(moved, STAY_WITHIN)

    def test_client_sends_no_further_goal_and_aborts(self):
        self.assertEqual(self.mission_run.state_names()[-1], 'aborted')
        # a goal the client sent as the cancel went out may be seen after the snapshot (the
        # goal topic is heard asynchronously); the server ends it at once (back_travel_server.test)
        later = len(self.mission_run.goals.snapshot()) - self.goals_at_cancel
        self.assertLessEqual(later, 1, '%d goals sent after the cancel' % later)
        self.assertLess(self.goals_at_cancel, self.landmarks, 'the cancel came after the last goal')
        ended = [msg for msg in self.mission_run.status.snapshot() if msg.state == 'aborted']
        self.assertTrue(ended, 'no status in state aborted')
        self.assertEqual({msg.outcome for msg in ended}, {MissionStatus.OUTCOME_CANCELLED},
                         ended[-1].reason)


if __name__ == '__main__':
    rospy.init_node('test_mission_cancel')
    rostest.rosrun('blind_navigation', 'mission_cancel', CancelTest)

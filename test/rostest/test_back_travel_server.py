#!/usr/bin/env python3
"""rostest: back_travel_server (distance mode) drives an ideal fake base: a goal
covers d, a curved goal's turn is mirrored, feedback flows, a cancel publishes
zero velocity at once, a bad goal is refused without moving the robot.

This node is the mission's owner (the server's ~mission_owner): it publishes the
state ``returning``, so the server takes its goals; another node's goals are
rejected, and so are goals once the mission has ended."""
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus

from blind_navigation.msg import BackTravelAction, BackTravelGoal

from fake_base import FakeBase
from mission_owner import MissionOwner

TIMEOUT = 20.0


class BackTravelServerTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_back_travel_server')
        cls.base = FakeBase()
        cls.client = actionlib.SimpleActionClient('/blind_navigation/back_travel', BackTravelAction)
        assert cls.client.wait_for_server(rospy.Duration(TIMEOUT)), 'server did not come up'
        cls.owner = MissionOwner('/back_travel_server')
        cls.owner.publish('returning')
        cls.owner.wait_until_server_takes_goals(cls.client, TIMEOUT)

    def send(self, **goal):
        feedback = []
        self.client.send_goal(BackTravelGoal(**goal), feedback_cb=feedback.append)
        return feedback

    def test_distance_goal_covers_d_with_feedback(self):
        x0 = self.base.x
        feedback = self.send(v=0.2, w=0.0, d=0.3, T=2.0, psi=0.0)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED)
        self.assertAlmostEqual(self.client.get_result().distance, 0.3, delta=0.02)
        self.assertGreaterEqual(len(feedback), 3, 'feedback at 5 Hz over 1.5 s')
        rospy.sleep(0.5)  # handover timeout: the server stops the base after the last goal
        self.assertEqual(self.base.commands[-1][1:], (0.0, 0.0))
        self.assertAlmostEqual(self.base.x - x0, 0.3, delta=0.03)

    def test_curved_goal_mirrors_the_turn(self):
        start = len(self.base.commands)
        self.send(v=0.1, w=0.3, d=0.1, T=1.0, psi=0.5)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        moving = [c for c in self.base.commands[start:] if c[1] != 0.0]
        self.assertTrue(moving, 'no command published')
        self.assertTrue(all(c[1:] == (0.1, -0.3) for c in moving), moving[:3])

    def test_cancel_publishes_zero_at_once(self):
        # a long goal (5 s at 0.2 m/s; d must be within what the base covers in T)
        self.send(v=0.2, w=0.0, d=1.0, T=5.0, psi=0.0)
        deadline = time.time() + 10.0
        while time.time() < deadline and self.base.v <= 0.0:
            time.sleep(0.02)
        self.assertGreater(self.base.v, 0.0, 'the goal did not drive the base within 10 s')
        cancelled = rospy.get_time()
        self.client.cancel_goal()
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED)
        deadline = time.time() + 2.0
        while time.time() < deadline and self.base.commands[-1][1:] != (0.0, 0.0):
            time.sleep(0.01)
        stamp, v, w = self.base.commands[-1]
        self.assertEqual((v, w), (0.0, 0.0), 'no zero velocity after cancel')
        self.assertLess(stamp - cancelled, 0.1, 'zero velocity came %.3f s after cancel'
                        % (stamp - cancelled))

    def test_bad_goal_is_refused_without_motion(self):
        start = len(self.base.commands)
        self.send(v=5.0, w=0.0, d=1.0, T=2.0, psi=0.0)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        self.assertEqual(self.client.get_state(), GoalStatus.ABORTED)
        self.assertIn('|v|', self.client.get_goal_status_text())
        self.assertFalse([c for c in self.base.commands[start:] if c[1:] != (0.0, 0.0)])


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'back_travel_server', BackTravelServerTest)

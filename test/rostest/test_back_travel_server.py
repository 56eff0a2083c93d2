#!/usr/bin/env python3
"""rostest: back_travel_server (distance mode) drives an ideal fake base: a goal
covers d, a curved goal's turn is mirrored, feedback flows, a cancel publishes
zero velocity at once, a bad goal is refused without moving the robot.

This node is the mission's owner (the server's ~mission_owner): it publishes the
state ``returning`` and, as back_travel_client does, sets the return's route
(blind_navigation/set_return_route) before each test's goals, which must be the
route's landmarks in order. Another node's goals are rejected, and so are the
owner's once the mission has ended."""
import math
import subprocess
import time
import unittest

import rospy
import rostest
from actionlib_msgs.msg import GoalID, GoalStatus
from rosgraph_msgs.msg import Log

from blind_navigation.msg import BackTravelAction, BackTravelActionResult, BackTravelGoal
from blind_navigation.ros.goal_client import GoalClient

from fake_base import FakeBase
from mission_owner import UNDRIVABLE, MissionOwner
from waiting import wait_for

TIMEOUT = 20.0


class BackTravelServerTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_back_travel_server')
        cls.base = FakeBase()
        cls.client = GoalClient('/blind_navigation/back_travel', BackTravelAction)
        assert cls.client.wait_for_server(rospy.Duration(TIMEOUT)), 'server did not come up'
        cls.owner = MissionOwner('/back_travel_server')
        cls.owner.publish('returning')
        cls.server_log = []
        rospy.Subscriber('/rosout', Log, lambda msg: cls.server_log.append(msg.msg)
                         if msg.name == '/back_travel_server' else None, queue_size=100)

    def drive(self, *goals):
        """Set the route of ``goals`` (landmark tuples) from where the base is, send the
        first; returns the feedback list it fills."""
        self.owner.set_route(goals, (self.base.x, self.base.y), TIMEOUT)
        return self.send(*goals[0])

    def send(self, *goal):
        feedback = []
        self.client.send_goal(BackTravelGoal(*goal), feedback_cb=feedback.append)
        return feedback

    def test_distance_goal_covers_d_with_feedback(self):
        wait_for(lambda: self.base.v == 0.0 and self.base.w == 0.0,
                 'the base still after the earlier tests\' goals', TIMEOUT)
        start = (self.base.x, self.base.y)      # heading: whatever earlier goals left
        feedback = self.drive((0.2, 0.0, 0.3, 2.0, 0.0))
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED)
        self.assertAlmostEqual(self.client.get_result().distance, 0.3, delta=0.02)
        self.assertGreaterEqual(len(feedback), 3, 'feedback at 5 Hz over 1.5 s')
        # after the last goal's hand-over time the server stops the base
        wait_for(lambda: self.base.commands[-1][1:] == (0.0, 0.0),
                 lambda: 'a zero command after the last goal; last %r' % (self.base.commands[-1],),
                 TIMEOUT)
        wait_for(lambda: self.base.v == 0.0, 'the base stopped after the goal', TIMEOUT)
        self.assertAlmostEqual(math.hypot(self.base.x - start[0], self.base.y - start[1]), 0.3,
                               delta=0.03)

    def test_curved_goal_mirrors_the_turn(self):
        start = len(self.base.commands)
        self.drive((0.1, 0.3, 0.1, 1.0, 0.5))
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        moving = [c for c in self.base.commands[start:] if c[1] != 0.0]
        self.assertTrue(moving, 'no command published')
        self.assertTrue(all(c[1:] == (0.1, -0.3) for c in moving), moving[:3])

    def test_cancel_of_every_goal_between_goals_ends_the_return(self):
        # as `rostopic pub .../cancel actionlib_msgs/GoalID {}` after a goal's end, before the
        # next goal: actionlib finds no goal to pass it to; the server ends the return itself
        wait_for(lambda: self.base.v == 0.0, 'the base still after the earlier tests\' goals', TIMEOUT)
        goal = (0.2, 0.0, 0.2, 1.0, 0.0)
        self.drive(goal, goal)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result of goal 1')
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED)
        cancel = rospy.Publisher('/blind_navigation/back_travel/cancel', GoalID, queue_size=1)
        wait_for(lambda: cancel.get_num_connections() >= 1, 'the server subscribing the cancel', TIMEOUT)
        cancel.publish(GoalID())
        wait_for(lambda: any('every goal cancelled between goals 1 and 2' in m for m in self.server_log),
                 lambda: 'the server ending the return between goals; its log %r' % self.server_log[-5:],
                 TIMEOUT)
        wait_for(lambda: self.base.v == 0.0, 'the base stopped after the cancel', TIMEOUT)
        after = len(self.base.commands)
        self.send(*goal)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result of goal 2')
        self.assertIn(self.client.get_state(), (GoalStatus.PREEMPTED, GoalStatus.RECALLED),
                      self.client.get_goal_status_text())
        self.assertFalse([c for c in self.base.commands[after:] if c[1:] != (0.0, 0.0)],
                         'goal 2 moved the base after every goal was cancelled')

    def test_cancel_publishes_zero_at_once(self):
        # a long goal (5 s at 0.2 m/s; d must be within what the base covers in T)
        self.drive((0.2, 0.0, 1.0, 5.0, 0.0))
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
        # screened when it arrives: rejected (it used to be accepted, then aborted); the
        # route set first (the server then sees the mission returning) holds another goal
        self.owner.set_route([(0.1, 0.0, 0.2, 2.0, 0.0)], (self.base.x, self.base.y), TIMEOUT)
        start = len(self.base.commands)
        self.send(5.0, 0.0, 1.0, 2.0, 0.0)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        self.assertEqual(self.client.get_state(), GoalStatus.REJECTED)
        self.assertIn('|v|', self.client.get_goal_status_text())
        self.assertFalse([c for c in self.base.commands[start:] if c[1:] != (0.0, 0.0)])

    def test_a_route_of_another_version_is_refused(self):
        goal = (0.1, 0.0, 0.2, 2.0, 0.0)
        self.owner.set_route([goal], (self.base.x, self.base.y), TIMEOUT)   # the server is returning
        start = len(self.base.commands)
        with self.assertRaisesRegex(AssertionError, 'route: version 2, this server reads version 1'):
            self.owner.set_route([goal], (self.base.x, self.base.y), TIMEOUT, version=2)
        self.assertFalse([c for c in self.base.commands[start:] if c[1:] != (0.0, 0.0)])

    def test_only_the_routes_next_landmark_is_taken(self):
        first, second = (0.1, 0.0, 0.1, 1.0, 0.0), (0.1, 0.0, 0.2, 2.0, 0.0)
        self.owner.set_route((first, second), (self.base.x, self.base.y), TIMEOUT)
        self.send(*second)
        self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
        self.assertEqual(self.client.get_state(), GoalStatus.REJECTED)
        self.assertIn('not the next landmark of the route', self.client.get_goal_status_text())
        for goal in (first, second):
            self.send(*goal)
            self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
            self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED,
                             self.client.get_goal_status_text())

    def test_goals_only_from_the_mission_owner_while_returning(self):
        self.owner.set_route([(0.1, 0.0, 0.2, 2.0, 0.0)], (self.base.x, self.base.y), TIMEOUT)
        start = len(self.base.commands)
        results = []
        subscriber = rospy.Subscriber('/blind_navigation/back_travel/result', BackTravelActionResult,
                                      results.append)
        try:
            # another node's goal (a second client) is rejected, even the route's next one;
            # its result proves the delivery: `rostopic pub -1` need not sit out its 3 s
            stranger_node = subprocess.Popen(
                ['rostopic', 'pub', '-1', '/blind_navigation/back_travel/goal',
                 'blind_navigation/BackTravelActionGoal',
                 "{goal_id: {id: 'stranger'}, goal: {v: 0.1, w: 0.0, d: 0.2, T: 2.0, psi: 0.0}}"],
                stdout=subprocess.DEVNULL)
            try:
                wait_for(lambda: [r for r in results if r.status.goal_id.id == 'stranger'],
                         'a result for the goal of another node', TIMEOUT)
            finally:
                stranger_node.terminate()
                stranger_node.wait(TIMEOUT)
        finally:
            subscriber.unregister()
        stranger = [r for r in results if r.status.goal_id.id == 'stranger'][0].status
        self.assertEqual(stranger.status, GoalStatus.REJECTED, stranger.text)
        self.assertIn('only %s sends back-travel goals' % rospy.get_name(), stranger.text)
        # the owner's goal once the mission has ended is rejected too
        self.owner.publish('home')
        try:
            deadline = time.monotonic() + TIMEOUT
            while True:     # until the server has seen the state, a probe is a bad goal
                self.client.send_goal(UNDRIVABLE)
                self.assertTrue(self.client.wait_for_result(rospy.Duration(TIMEOUT)), 'no result')
                text = self.client.get_goal_status_text()
                if 'the mission is' in text or time.monotonic() > deadline:
                    break
                time.sleep(0.05)
            self.assertEqual(self.client.get_state(), GoalStatus.REJECTED)
            self.assertIn('the mission is home', text)
        finally:
            self.owner.publish('returning')
        self.assertFalse([c for c in self.base.commands[start:] if c[1:] != (0.0, 0.0)],
                         'a rejected goal moved the base')


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'back_travel_server', BackTravelServerTest)

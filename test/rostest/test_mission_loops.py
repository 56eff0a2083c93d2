#!/usr/bin/env python3
"""rostest: a mission whose path comes back to where it has been, on the fake
TurtleBot with blind_navigation.launch as a user starts it (one process,
prune_loops at its default): the return is pruned (issue 15).

The layer records while the fake's scripted operator plays ``~mission`` (started
by this node once the layer records); then vision is lost (published by this
node). Asserted: the state walks idle -> recording -> rotating -> returning ->
home; every landmark's goal succeeded (the protocol is one goal per landmark,
pruned or not); the client logged its cuts; the latched return route
(/blind_navigation/return_route) is the pruned one, shorter than
``~max_return_share`` of the recorded path; the return the robot really drove
(ground truth after the pi turn) is shorter than ``~max_return_share`` of the
path it drove while recording; it ends within ``~max_error`` m of its start.
With ``~record_rtf`` the fake's clock runs at that rtf while the mission is
recorded and at the launch's rtf from the vision loss on.
"""
import math
import os
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Path
from rosgraph_msgs.msg import Log

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import HomeMission, MissionRun, PathByState  # noqa: E402
from recording_tools import Collector  # noqa: E402

from blind_navigation import names  # noqa: E402


def path_length(path):
    points = [(p.pose.position.x, p.pose.position.y) for p in path.poses]
    return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(points, points[1:]))


class LoopMissionTest(HomeMission, unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission = rospy.get_param('~mission')
        cls.max_error = float(rospy.get_param('~max_error'))
        cls.max_share = float(rospy.get_param('~max_return_share'))
        cls.mission_run = MissionRun(float(rospy.get_param('~wall_timeout', 300.0)))
        cls.paths = PathByState()
        cls.route = Collector(names.RETURN_ROUTE, Path)
        cls.log = Collector('/rosout', Log)
        try:
            cls.mission_run.record_mission(cls.mission, rospy.get_param('~record_rtf', 0.0))
            cls.mission_run.trigger_by_publisher()
            cls.error, _, cls.loaded = cls.mission_run.outcome()
        finally:
            cls.mission_run.stop_operator()
        cls.mission_run.wait(lambda: cls.route.snapshot(), 'no %s was published' % names.RETURN_ROUTE)
        rospy.loginfo('LOOPS %s: state %s, forward %.2f m, return %.2f m, route %.2f m of %.2f m recorded, '
                      'error %.3f m', cls.mission, cls.mission_run.state_names()[-1], cls.paths.of('recording'),
                      cls.paths.of('return'), path_length(cls.route.snapshot()[-1]),
                      cls.loaded.total_distance, cls.error)

    def test_every_landmark_is_still_a_goal_and_succeeded(self):
        self.assert_every_landmark_succeeded(10)

    def test_the_client_logged_its_cuts(self):
        lines = [m.msg for m in self.log.snapshot() if 'back_travel_client: cut a ' in m.msg]
        self.assertTrue(lines, 'the client logged no "cut a ..." line on /rosout')
        self.assertIn('drift std', lines[0])

    def test_the_published_route_is_the_pruned_one(self):
        route = path_length(self.route.snapshot()[-1])
        self.assertLess(route, self.max_share * self.loaded.total_distance,
                        'return_route %.2f m of %.2f m recorded' % (route, self.loaded.total_distance))

    def test_the_return_driven_is_shorter_than_the_share_of_the_forward_path(self):
        forward, back = self.paths.of('recording'), self.paths.of('return')
        self.assertGreater(forward, 0.9 * self.loaded.total_distance)
        self.assertLess(back, self.max_share * forward,
                        'returned %.2f m after %.2f m forward' % (back, forward))

    def test_robot_ends_near_its_start(self):
        self.assertLessEqual(self.error, self.max_error)


if __name__ == '__main__':
    rospy.init_node('test_mission_loops')
    rostest.rosrun('blind_navigation', 'mission_loops', LoopMissionTest)

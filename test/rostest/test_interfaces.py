#!/usr/bin/env python3
"""rostest: the package's message, service and action definitions are generated
and usable over a real ROS master (topic, service and actionlib round trips)."""
import unittest

import actionlib
import rospy
import rostest

from blind_navigation.msg import (BackTravelAction, BackTravelFeedback, BackTravelGoal,
                                  BackTravelResult, PathSample)
from blind_navigation.srv import RecordLandmark, RecordLandmarkResponse

TIMEOUT = 10.0


class InterfacesTest(unittest.TestCase):

    def test_path_sample_has_the_papers_three_variables(self):
        # and which sample it is, for a restarted recorder (srv/RecordedSamples.srv)
        self.assertEqual(PathSample.__slots__, ['header', 'command', 'yaw', 'period',
                                                'recording', 'seq'])

    def test_action_goal_is_a_landmark(self):
        self.assertEqual(BackTravelGoal.__slots__, ['v', 'w', 'd', 'T', 'psi'])
        self.assertEqual(BackTravelResult.__slots__, ['distance', 'duration'])
        self.assertEqual(BackTravelFeedback.__slots__, ['distance'])

    def test_topic_round_trip(self):
        received = []
        rospy.Subscriber('interfaces_test/sample', PathSample, received.append)
        publisher = rospy.Publisher('interfaces_test/sample', PathSample, queue_size=1)
        deadline = rospy.Time.now() + rospy.Duration(TIMEOUT)
        while not received and rospy.Time.now() < deadline and not rospy.is_shutdown():
            publisher.publish(PathSample(command='sample', yaw=0.25, period=2.0))
            rospy.sleep(0.1)
        self.assertTrue(received, 'no PathSample came back within %.0f s' % TIMEOUT)
        self.assertEqual((received[0].command, received[0].yaw, received[0].period),
                         ('sample', 0.25, 2.0))

    def test_service_round_trip(self):
        def handle(request):
            return RecordLandmarkResponse(saved=True, label='landmark_000001', message='')
        rospy.Service('interfaces_test/record', RecordLandmark, handle)
        rospy.wait_for_service('interfaces_test/record', timeout=TIMEOUT)
        response = rospy.ServiceProxy('interfaces_test/record', RecordLandmark)(
            command='sample', yaw=0.1, period=1.0)
        self.assertTrue(response.saved)
        self.assertEqual(response.label, 'landmark_000001')

    def test_action_round_trip(self):
        def execute(goal):
            server.publish_feedback(BackTravelFeedback(distance=goal.d / 2))
            server.set_succeeded(BackTravelResult(distance=goal.d, duration=goal.T))
        server = actionlib.SimpleActionServer('interfaces_test/back_travel', BackTravelAction,
                                              execute_cb=execute, auto_start=False)
        server.start()
        client = actionlib.SimpleActionClient('interfaces_test/back_travel', BackTravelAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(TIMEOUT)),
                        'action server did not come up within %.0f s' % TIMEOUT)
        client.send_goal(BackTravelGoal(v=0.1, w=0.0, d=0.2, T=2.0, psi=0.0))
        self.assertTrue(client.wait_for_result(rospy.Duration(TIMEOUT)), 'no action result')
        self.assertEqual(client.get_result().distance, 0.2)


if __name__ == '__main__':
    rospy.init_node('test_interfaces')
    rostest.rosrun('blind_navigation', 'interfaces', InterfacesTest)

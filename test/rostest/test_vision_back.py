#!/usr/bin/env python3
"""rostest (vision_back_paper.test): paper.launch keeps the paper's behaviour on the fake
TurtleBot: after the mission the fake's vision fails (``fake_turtlebot/set_vision``, dark
images and lost visual odometry) for ``~loss`` s of sim time; the vision monitor detects it,
the mission turns and returns home at once (vision_back_grace 0, on_vision_back home) and
vision coming back during the return changes nothing: home within the paper's time-mode
bound. (The default launch's brief loss and on_vision_back stop: the harness,
test/unit/test_mission_harness.py and test_mission_scenarios.py.)
"""
import os
import sys
import unittest

import rospy
import rostest
from std_srvs.srv import SetBool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mission_tools import MissionRun  # noqa: E402
from recording_tools import Collector  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.msg import MissionStatus  # noqa: E402
from blind_navigation.sim.node_common import SET_VISION  # noqa: E402

#: m, the paper's time mode on the left arc (lane_mission_left_arc_time.test's bound and why)
PAPER_MAX_ERROR = 0.59


class VisionBackTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        mission = rospy.get_param('~mission')
        cls.run_ = run = MissionRun(float(rospy.get_param('~wall_timeout', 200.0)))
        cls.status = Collector(names.STATUS, MissionStatus)
        rospy.wait_for_service(SET_VISION, timeout=30.0)
        set_vision = rospy.ServiceProxy(SET_VISION, SetBool)
        try:
            run.wait_for_layer()
            run.start_operator(mission)
            run.wait_for_operator(mission)
            set_vision(False)
            run.wait_sim(float(rospy.get_param('~loss')), 'the vision loss')
            set_vision(True)
            cls.outcome = run.outcome()
        finally:
            run.stop_operator()
        cls.loaded = run.recorded()

    @classmethod
    def tearDownClass(cls):
        cls.run_.remove_recording()

    def reasons(self, state):
        return [msg.reason for msg in self.status.snapshot() if msg.state == state]

    def test_vision_back(self):
        self.assertEqual(self.run_.state_names(), ['idle', 'recording', 'rotating', 'returning', 'home'])
        self.assertTrue(self.reasons('rotating')[0].startswith('vision lost'), self.reasons('rotating'))
        rospy.loginfo('PAPER LOSS: home within %.4f m on a %.2f m path', self.outcome.error,
                      self.loaded.total_distance)
        # the paper's time mode on the ideal fake: lane_mission_left_arc_time.test's bound
        self.assertLess(self.outcome.error, PAPER_MAX_ERROR)


if __name__ == '__main__':
    rospy.init_node('test_vision_back')
    rostest.rosrun('blind_navigation', 'test_vision_back', VisionBackTest)

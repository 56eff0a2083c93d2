#!/usr/bin/env python3
"""rostest of a Python lane (lane_*.test): test/rostest/test_mission.py's mission, then
interpreter_check.py's check, as one test node in one launch (rostest starts a .test's
launch afresh for each <test>). The check runs once the mission is home, while the
layer's nodes still run."""
import os
import sys

import rospy
import rostest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, '..', 'rostest')]
from interpreter_check import InterpreterTest  # noqa: E402
from test_mission import MissionTest  # noqa: E402


class LaneMissionTest(MissionTest, InterpreterTest):
    """MissionTest's setUpClass plays the mission; then its cases and the interpreter check."""


if __name__ == '__main__':
    rospy.init_node('lane_mission')
    rostest.rosrun('blind_navigation', 'lane_mission', LaneMissionTest)

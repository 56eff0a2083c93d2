#!/usr/bin/env python3
"""rostest: the trigger chain. A left arc was recorded (landmarks written by the
test, the fake base starts at the arc's end); a storage moves the state to
recording; `rostopic pub -1 .../vision_lost` makes rotate_pi turn by pi and the
client drive the landmarks back: states rotating, returning, home; the base
ends at the arc's start, and /blind_navigation/return_path is published."""
import math
import os
import subprocess
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Path
from std_msgs.msg import String

from blind_navigation.core.landmark import Landmark
from blind_navigation.core.progress import progress_path
from blind_navigation.core.landmark_writer import LandmarkWriter
from blind_navigation.msg import StorageUsage

from fake_base import FakeBase

TIMEOUT = 90.0
V, W, T, N = 0.1, 0.2, 1.0, 6   # left arc, radius 0.5 m, 1.2 rad
RADIUS = V / W


def arc_landmarks():
    chord = 2 * RADIUS * math.sin(W * T / 2)
    return [Landmark(V, W, chord, T, W * T * k) for k in range(1, N + 1)]


class TriggerTest(unittest.TestCase):

    def test_vision_lost_by_rostopic_pub_brings_the_robot_home(self):
        rospy.init_node('test_back_travel_trigger')
        path = rospy.get_param('~landmark_file')
        os.makedirs(os.path.dirname(path), exist_ok=True)
        for stale in (path, progress_path(path)):   # a progress file left over would resume
            if os.path.exists(stale):
                os.remove(stale)
        with LandmarkWriter(path, fsync=False) as writer:
            for landmark in arc_landmarks():
                writer.append(landmark)
        end_yaw = W * T * N
        base = FakeBase(x=RADIUS * math.sin(end_yaw), y=RADIUS * (1 - math.cos(end_yaw)), yaw=end_yaw)
        states, paths = [], []
        rospy.Subscriber('/blind_navigation/state', String, lambda m: states.append(m.data))
        rospy.Subscriber('/blind_navigation/return_path', Path, paths.append)
        storage = rospy.Publisher('/blind_navigation/storage', StorageUsage, queue_size=1, latch=True)
        self.wait_for(lambda: states[-1:] == ['idle'], 'client publishes idle')
        storage.publish(StorageUsage(file=path, landmarks=N, distance=N * V * T))
        self.wait_for(lambda: states[-1:] == ['recording'], 'state recording after a storage')
        time.sleep(1.0)  # rotate_pi has seen the latched state
        subprocess.check_call(['rostopic', 'pub', '-1', '/blind_navigation/vision_lost',
                               'std_msgs/Empty', '{}'], timeout=30)
        self.wait_for(lambda: states[-1:] in (['home'], ['aborted']), 'state home or aborted')
        self.assertEqual(states, ['idle', 'recording', 'rotating', 'returning', 'home'])
        error = math.hypot(base.x, base.y)
        self.assertLess(error, 0.03, 'base ended %.3f m from the arc start (%.3f, %.3f)'
                        % (error, base.x, base.y))
        self.assertTrue(paths and len(paths[-1].poses) > 10, 'return_path not published')

    def wait_for(self, condition, what):
        deadline = time.time() + TIMEOUT
        while not condition() and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)
        self.assertTrue(condition(), 'timed out after %.0f s waiting for: %s' % (TIMEOUT, what))


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'back_travel_trigger', TriggerTest)

#!/usr/bin/env python3
"""rostest: a layer killed (SIGKILL) mid-return and restarted resumes from the
last completed landmark and still ends ``home`` at the start; the recorded file
is never modified; the restarted recorder starts a new file behind the symlink
and keeps the old one; the layer writes nothing but the progress file and the
recorder's new file, all in the landmark directory."""
import os
import shutil
import signal
import unittest

import rospy
import rostest

from blind_navigation.core.progress import file_digest, load_progress, progress_path
from blind_navigation.msg import BackTravelActionGoal

from fake_base import FakeBase
from safety_rig import (Collector, Layer, Node, SimClock, distance_from_origin, path_length,
                        straight_landmarks, write_mission)
from waiting import wait_for

COUNT = 10
KILL_AFTER = 4          # completed landmarks before the layer is killed


class ResumeTest(unittest.TestCase):

    def test_restart_mid_return_resumes_and_ends_home(self):
        rospy.init_node('test_safety_resume')
        SimClock(rtf=2.0)
        directory = rospy.get_param('~directory')
        shutil.rmtree(directory, ignore_errors=True)
        landmarks = straight_landmarks([0.1] * COUNT)
        link, recorded = write_mission(directory, landmarks)
        digest, mtime = file_digest(recorded), os.stat(recorded).st_mtime_ns
        progress_file = progress_path(link)
        if os.path.exists(progress_file):
            os.remove(progress_file)
        base = FakeBase(x=path_length(landmarks), yaw=3.141592653589793)
        layer = Layer()
        goals = Collector('/blind_navigation/back_travel/goal', BackTravelActionGoal)

        nodes = [Node('back_travel_server.py', 'back_travel_server'),
                 Node('back_travel_client.py', 'back_travel_client', {'landmark_file': link})]
        layer.walk_to_returning(0)
        wait_for(lambda: os.path.exists(progress_file)
                 and load_progress(progress_file).completed >= KILL_AFTER,
                 '%d landmarks completed' % KILL_AFTER, timeout=90.0)
        for node in nodes:
            node.kill(signal.SIGKILL)
        done_at_kill = load_progress(progress_file).completed
        at_kill = (base.x, base.y)
        self.assertLess(done_at_kill, COUNT, 'the return ended before the kill')
        wait_for(lambda: base.v == 0.0, 'the base stops on its command timeout')

        restart_states, restart_goals = len(layer.states), len(goals)
        nodes = [Node('landmark_saver.py', 'landmark_saver', {'landmark_file': link, 'fsync': 'false'}),
                 Node('back_travel_server.py', 'back_travel_server'),
                 Node('back_travel_client.py', 'back_travel_client', {'landmark_file': link})]
        try:
            final = layer.wait_final(restart_states, timeout=120.0)
            states = layer.state_list(restart_states)
            self.assertEqual(final, 'home', layer.abort_reason('/back_travel_client'))
            self.assertEqual(states, ['returning', 'home'], 'resumed, not started over')
            # Only the landmarks not completed are sent again. The restarted client sends its
            # first goal as soon as it is up, possibly before this node's subscription to it
            # connects (rospy), so that one may go unseen (1 run in 5 on a loaded machine); a
            # landmark really skipped would leave the robot 0.2 m short (asserted below).
            resent = len(goals) - restart_goals
            self.assertIn(resent, (COUNT - done_at_kill - 1, COUNT - done_at_kill),
                          'goals after the restart: only the %d landmarks not completed'
                          % (COUNT - done_at_kill))
            print('RESUME: killed after %d of %d landmarks at (%.3f, %.3f); %d goals after the '
                  'restart; ended %.3f m from the start'
                  % (done_at_kill, COUNT, at_kill[0], at_kill[1], len(goals) - restart_goals,
                     distance_from_origin(base)), flush=True)
            self.assertLess(distance_from_origin(base), 0.05, 'ended %.3f m from the start'
                            % distance_from_origin(base))
            progress = load_progress(progress_file)
            self.assertEqual((progress.status, progress.completed), ('home', COUNT))
            self.assertEqual(progress.landmark_file, recorded)
        finally:
            for node in nodes:
                node.kill()
        self.assertEqual((file_digest(recorded), os.stat(recorded).st_mtime_ns), (digest, mtime),
                         'the recorded file was modified')
        new_file = os.path.join(directory, os.readlink(link))
        self.assertNotEqual(new_file, recorded, 'the restarted recorder did not start a new file')
        self.assertTrue(os.path.isfile(new_file))
        self.assertEqual(sorted(os.listdir(directory)),
                         sorted(['landmarks.yaml', 'landmarks.progress.yaml',
                                 os.path.basename(recorded), os.path.basename(new_file)]))


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'safety_resume', ResumeTest)

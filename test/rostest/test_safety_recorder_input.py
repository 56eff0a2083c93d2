#!/usr/bin/env python3
"""rostest: bad input to the recording layer. Odometry with NaN or a zero
quaternion (bursts between good messages, with absurd positions) is never
recorded and is warned about at a limited rate; path-like strings in
PathSample.command, RecordLandmark.command, StorageUsage.file and the state
topic never make the layer write outside its directory; a saver restarted
within the same mission (``blind_navigation/mission_id``) continues the
mission's file (finished: it adds nothing), one started for a new mission
starts a new file behind the symlink and keeps the old one unchanged. This
node owns the mission (the sampling publisher's ~mission_owner): it ends the
recording by moving the state to rotating (vision lost)."""
import math
import os
import subprocess
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from std_msgs.msg import Header, String

from blind_navigation.core.progress import file_digest
from blind_navigation.core.store import load_landmarks
from blind_navigation.msg import StorageUsage, PathSample
from blind_navigation.srv import RecordLandmark

from mission_owner import MissionOwner
from recording_tools import Diagnostics
from safety_rig import Collector, Node, SimClock
from waiting import wait_for

SPEED = 0.1             # m/s along +x
RECORD_TIME = 12.0      # s of sim time recorded
TOKEN = 'bn_escape_%d' % os.getpid()
EVIL = ['../../../../../../tmp/%s/a.yaml' % TOKEN, '/tmp/%s/b.yaml' % TOKEN,
        '~/%s.yaml' % TOKEN, '../%s.yaml' % TOKEN, 'sample/../../%s' % TOKEN]


class Odometer(object):
    """Good odometry at 50 Hz (sim) along +x; every 10th message is NaN and every
    10th+5 has a zero quaternion, both with an absurd position."""

    def __init__(self):
        self.pub = rospy.Publisher('/odom', Odometry, queue_size=50)
        self.count = self.bad = 0
        self.timer = rospy.Timer(rospy.Duration(0.02), self._tick)
        self.t0 = rospy.get_time()

    def _tick(self, _event):
        msg = Odometry()
        msg.header.stamp = rospy.Time.now()
        msg.header.frame_id = 'odom'
        msg.pose.pose.position.x = SPEED * (rospy.get_time() - self.t0)
        msg.pose.pose.orientation.w = 1.0
        msg.twist.twist.linear.x = SPEED
        self.count += 1
        if self.count % 10 == 0:
            msg.pose.pose.position.x, msg.twist.twist.linear.x = float('nan'), 5.0
            self.bad += 1
        elif self.count % 10 == 5:
            msg.pose.pose.position.x = 1e6
            msg.pose.pose.orientation.w = 0.0
            self.bad += 1
        try:
            self.pub.publish(msg)
        except rospy.ROSException:
            pass


class RecorderInputTest(unittest.TestCase):

    def test_bad_odometry_and_path_like_strings(self):
        rospy.init_node('test_safety_recorder_input')
        clock = SimClock(rtf=2.0)
        directory = rospy.get_param('~directory')
        link = os.path.join(directory, 'landmarks.yaml')
        rosout = Collector('/rosout', __import__('rosgraph_msgs.msg', fromlist=['Log']).Log)
        diagnostics = Diagnostics()
        wait_for(lambda: os.path.islink(link), 'the saver created its mission file', 60.0)
        first_file = os.path.realpath(link)
        odometer = Odometer()
        samples = rospy.Publisher('/blind_navigation/sample', PathSample, queue_size=10)
        storage = rospy.Publisher('/blind_navigation/storage', StorageUsage, queue_size=10)
        state = rospy.Publisher('/blind_navigation/state', String, queue_size=10)
        rospy.wait_for_service('/blind_navigation/record_landmark', 60.0)
        record = rospy.ServiceProxy('/blind_navigation/record_landmark', RecordLandmark)
        start = rospy.get_time()
        refusals = []
        while rospy.get_time() - start < RECORD_TIME:
            for text in EVIL:
                samples.publish(PathSample(header=Header(stamp=rospy.Time.now()), command=text,
                                           yaw=0.0, period=1.0))
                refusals.append(record(header=Header(stamp=rospy.Time.now()), command=text,
                                       yaw=0.0, period=1.0))
                storage.publish(StorageUsage(file=text, landmarks=1))
                state.publish(String(data=text))
            rospy.sleep(1.0)
        MissionOwner('/sampling_publisher').publish('rotating')    # vision lost: recording ends
        # the status is published every second, a log line once (a loaded machine's /rosout
        # queue may drop it): wait on the status, and name the roles' last lines if it never comes
        finished = 'landmark_saver: landmark_saver: recording'

        def said():
            return [m.msg for _, m in rosout.items[-200:]
                    if m.name in ('/landmark_saver', '/sampling_publisher')][-6:]
        wait_for(lambda: 'recording finished' in (diagnostics.status(finished) or ('',))[0],
                 lambda: 'the saver finished (status %s; last lines %s)'
                 % (diagnostics.status(finished), said()), 60.0)

        self.assertTrue(refusals and not any(r.saved for r in refusals))
        self.assertTrue(all('unknown command' in r.message for r in refusals), refusals[0])
        loaded = load_landmarks(first_file)
        self.assertGreaterEqual(len(loaded.landmarks), 4, 'too few landmarks recorded')
        for label, lm in zip(loaded.labels, loaded.landmarks):
            self.assertTrue(all(math.isfinite(value) for value in lm), label)
            self.assertAlmostEqual(lm.v, SPEED, delta=1e-6, msg='%s: bad odometry used' % label)
            self.assertLessEqual(lm.d, SPEED * lm.T + 0.03, '%s: bad odometry used' % label)
        warnings = [m.msg for _, m in rosout.items if m.name == '/landmark_saver' and 'not used' in m.msg]
        elapsed = rospy.get_time() - start
        print('RECORDER INPUT: %d bad odometry messages of %d, %d throttled warnings in %.0f s sim, '
              '%d landmarks' % (odometer.bad, odometer.count, len(warnings), elapsed,
                                len(loaded.landmarks)), flush=True)
        self.assertGreaterEqual(len(warnings), 1, 'bad odometry was not warned about')
        self.assertLessEqual(len(warnings), elapsed / 5.0 + 2, 'warnings not rate-limited')

        digest = file_digest(first_file)
        saver2 = Node('landmark_saver.py', 'landmark_saver_restarted',
                      {'landmark_file': link, 'fsync': 'false'})
        restarted = 'landmark_saver_restarted: landmark_saver: recording'
        try:
            wait_for(lambda: diagnostics.status(restarted, 'file'), 'diagnostics of the restarted saver',
                     60.0)
        finally:
            saver2.kill()
        summary, values = diagnostics.status(restarted, 'file')
        self.assertEqual(values['file'], first_file, 'the restarted saver did not continue its file')
        self.assertEqual(summary, 'recording finished: %d landmarks' % len(loaded.landmarks))
        self.assertEqual(os.path.realpath(link), first_file, 'the restarted saver left the mission\'s file')
        self.assertEqual(file_digest(first_file), digest, 'the finished mission file changed')
        rospy.set_param('/blind_navigation/mission_id', 'next_' + rospy.get_param('/blind_navigation/mission_id'))
        saver3 = Node('landmark_saver.py', 'landmark_saver_next_mission',
                      {'landmark_file': link, 'fsync': 'false'})
        try:
            wait_for(lambda: diagnostics.status('landmark_saver_next_mission: landmark_saver: recording',
                                                'file'), 'diagnostics of the saver of a new mission', 60.0)
        finally:
            saver3.kill()
        self.assertNotEqual(os.path.realpath(link), first_file, 'the saver of a new mission did not '
                            'start a new file')
        self.assertEqual(file_digest(first_file), digest, 'the old mission file changed')
        self.assertEqual(sorted(os.listdir(directory)), sorted(
            ['landmarks.yaml', 'service', os.path.basename(first_file),
             os.path.basename(os.path.realpath(link))]))
        self.assertEqual(len(os.listdir(os.path.join(directory, 'service'))), 2,
                         'the record server wrote more than its mission file and symlink')
        escaped = subprocess.run(['find', '/tmp', os.environ.get('ROS_HOME', '/tmp'),
                                  os.path.dirname(directory), '-maxdepth', '8', '-name', '*%s*' % TOKEN],
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                 universal_newlines=True, timeout=120).stdout.split()
        self.assertEqual(escaped, [], 'files written outside the landmark directory')
        del clock


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'safety_recorder_input', RecorderInputTest)

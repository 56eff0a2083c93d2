#!/usr/bin/env python3
"""rostest: the recording layer on the fake TurtleBot (paper noise, a Table VI mission).

Three recorders take the same sampling publisher's ticks: the topic variant
(recording.launch's landmark_saver), the service variant (record_server +
record_client) and a second topic saver that is killed with SIGKILL
mid-mission. When the scripted operator is done, vision is lost (this node,
the sampling publisher's ~mission_owner, moves the mission state to rotating)
and the files are checked:

- periods are only the configured ones (except the final partial cycle) and are
  what the paper's classifier gives on the recorded yaws (that the rate follows
  a real curve is recording_curves.test: this mission's weaves, driven by the
  operator model, are lane changes of ~0.1 rad too short for four yaws 2 s
  apart to see, as with the paper's own rule);
- landmark count and file size are in the paper's Table VI range;
- topic and service variants agree within one odometry message;
- the yaml-cpp reader reads the numbers PyYAML reads;
- the killed saver's file loads and holds every landmark it reported.
"""
import math
import os
import shutil
import sys
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from recording_tools import Collector, kill_node, landmark_info, subscribers_of, wait_for  # noqa: E402

from blind_navigation import names
from blind_navigation.sim.mission import load_mission  # noqa: E402
from blind_navigation.core.segment import SamplingSchedule  # noqa: E402
from blind_navigation.core.store import load_landmarks  # noqa: E402
from blind_navigation.msg import StorageUsage, PathSample  # noqa: E402
from mission_owner import MissionOwner  # noqa: E402

STRAIGHT_T, CURVED_T = 2.0, 1.0
#: Paper Table VI: 35-137 samples and 4-14 KB over 2.6-13.2 m.
PAPER_SAMPLES = (35, 137)
PAPER_BYTES = (4 * 1024, 14 * 1024)
MISSION_WALL_TIMEOUT = 150.0    # s wall for the whole mission (~154 s sim at rtf 10)


class OdometryJitter(object):
    """Largest change of v, w and position between consecutive /odom messages:
    what two recorders reading odometry one message apart can differ by."""

    def __init__(self):
        self.previous = None
        self.max_dv = self.max_dw = self.max_step = 0.0
        self.sub = rospy.Subscriber('/odom', Odometry, self.on_odom, queue_size=100)

    def on_odom(self, msg):
        p, t = msg.pose.pose.position, msg.twist.twist
        current = (p.x, p.y, t.linear.x, t.angular.z)
        if self.previous:
            px, py, pv, pw = self.previous
            self.max_dv = max(self.max_dv, abs(current[2] - pv))
            self.max_dw = max(self.max_dw, abs(current[3] - pw))
            self.max_step = max(self.max_step, math.hypot(current[0] - px, current[1] - py))
        self.previous = current


class FakeTurtleBotRecordingTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.mission = load_mission(rospy.get_param('~mission'))
        cls.files = {name: rospy.get_param('~%s_file' % name) for name in ('topic', 'service', 'killed')}
        cls.samples = Collector(names.SAMPLE, PathSample)
        cls.storage_msgs = Collector(names.STORAGE, StorageUsage)
        cls.jitter = OdometryJitter()
        done = Collector('/mission_driver/done', Bool)
        owner = MissionOwner('/sampling_publisher')
        owner.publish('recording')
        wait_for(lambda: {'/landmark_saver', '/record_client', '/landmark_saver_killed'}
                 <= subscribers_of(names.SAMPLE), 'the recorders never subscribed to the samples')
        cls.killed = {}
        wait_for(lambda: cls.kill_when_half_done(), 'the killed saver never reached mid-mission',
                 timeout=MISSION_WALL_TIMEOUT)
        wait_for(lambda: any(msg.data for msg in done.snapshot()), 'the mission never finished',
                 timeout=MISSION_WALL_TIMEOUT)
        owner.publish('rotating')    # vision lost: the mission's owner ends the recording
        wait_for(lambda: any(s.command == 'final' for s in cls.samples.snapshot()),
                 'no final sample after the mission moved to rotating')
        ticks = sum(s.command in ('sample', 'final') for s in cls.samples.snapshot())
        wait_for(lambda: cls.saved_by(cls.files['topic']) >= ticks
                 and cls.saved_by(cls.files['service']) >= ticks,
                 'the topic and service variants did not save all %d ticks' % ticks)
        cls.loaded = {name: load_landmarks(path) for name, path in cls.files.items()}

    @classmethod
    def saved_by(cls, landmark_file):
        target = os.path.realpath(landmark_file)
        return max([msg.landmarks for msg in cls.storage_msgs.snapshot()
                    if os.path.realpath(msg.file) == target] or [0])

    @classmethod
    def kill_when_half_done(cls):
        if cls.saved_by(cls.files['killed']) < 30:
            return False
        cls.killed['reported'] = cls.saved_by(cls.files['killed'])
        cls.killed['pid'] = kill_node('/landmark_saver_killed')
        cls.killed['at'] = rospy.Time.now().to_sec()
        return True

    @classmethod
    def tearDownClass(cls):
        directory = os.path.dirname(cls.files['topic'])
        if directory.endswith('-recording-test'):       # only the launch's private directory
            shutil.rmtree(directory, ignore_errors=True)

    def test_periods_are_the_configured_ones_and_follow_the_classifier(self):
        for name in ('topic', 'service'):
            landmarks = self.loaded[name].landmarks
            self.assertEqual({lm.T for lm in landmarks[:-1]}, {STRAIGHT_T, CURVED_T}, name)
            self.assertLess(landmarks[-1].T, STRAIGHT_T + 0.1, name)
            # The paper's rule on the recorded yaws gives each next period (from the
            # fifth landmark on: the first windows include the unrecorded start yaw).
            schedule = SamplingSchedule(STRAIGHT_T, CURVED_T)
            expected = [schedule.update(landmark.psi) for landmark in landmarks[:-2]]
            self.assertEqual([lm.T for lm in landmarks[4:-1]], expected[3:], name)

    def test_storage_in_the_papers_range(self):
        loaded = self.loaded['topic']
        count, size = len(loaded.landmarks), os.path.getsize(loaded.path)
        rospy.loginfo('storage %s: %d landmarks, %d bytes, %.2f m, %.0f B/m, %.1f B/landmark',
                      self.mission.name, count, size, loaded.total_distance,
                      size / loaded.total_distance, size / count)
        self.assertTrue(PAPER_SAMPLES[0] <= count <= PAPER_SAMPLES[1], count)
        self.assertTrue(PAPER_BYTES[0] <= size <= PAPER_BYTES[1], size)

    def test_topic_and_service_agree_within_one_odometry_message(self):
        topic, service = self.loaded['topic'].landmarks, self.loaded['service'].landmarks
        self.assertEqual(len(topic), len(service))
        # Each landmark reads the latest odometry: the two recorders may be one
        # message apart at each end of a landmark (+ 6-significant-digit rounding).
        for index, (a, b) in enumerate(zip(topic, service)):
            where = 'landmark %d' % (index + 1)
            self.assertEqual((a.T, a.psi), (b.T, b.psi), where)
            self.assertLessEqual(abs(a.v - b.v), self.jitter.max_dv + 1e-5, where)
            self.assertLessEqual(abs(a.w - b.w), self.jitter.max_dw + 1e-5, where)
            if index > 0:   # landmark 1's d counts from each saver's odometry at the
                # publisher's start; at rtf 10 a saver's odometry subscription may
                # connect a few messages after that (start-up race, see docs/recording.md)
                self.assertLessEqual(abs(a.d - b.d), 2 * self.jitter.max_step + 1e-5, where)

    def test_yaml_cpp_reader_reads_what_pyyaml_reads(self):
        for name, loaded in self.loaded.items():
            info = landmark_info(loaded.path)
            self.assertEqual(list(info['data']), loaded.labels, name)
            self.assertEqual([tuple(values) for values in info['data'].values()],
                             [tuple(lm) for lm in loaded.landmarks], name)
            self.assertAlmostEqual(info['distance_m'], loaded.total_distance, places=9)
            self.assertAlmostEqual(info['duration_s'], sum(lm.T for lm in loaded.landmarks), places=9)

    def test_killed_saver_file_holds_every_landmark_it_reported(self):
        self.assertIn('pid', self.killed, 'the saver was not killed')
        killed, topic = self.loaded['killed'].landmarks, self.loaded['topic'].landmarks
        self.assertGreaterEqual(len(killed), self.killed['reported'])
        sent = [s for s in self.samples.snapshot() if s.header.stamp.to_sec() <= self.killed['at']]
        self.assertLessEqual(len(killed), len(sent))
        self.assertLess(len(killed), len(topic), 'the kill was not mid-mission')
        for index, (a, b) in enumerate(zip(killed, topic)):
            self.assertEqual((a.T, a.psi), (b.T, b.psi), 'landmark %d' % (index + 1))


if __name__ == '__main__':
    rospy.init_node('test_recording_fake')
    rostest.rosrun('blind_navigation', 'recording_fake_turtlebot', FakeTurtleBotRecordingTest)

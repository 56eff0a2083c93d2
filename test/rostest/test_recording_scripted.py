#!/usr/bin/env python3
"""rostest: the recording layer (launch/recording.launch) on scripted odometry.

This test node owns sim time: it publishes /clock and nav_msgs/Odometry for a
scripted straight/arc/straight path (test/scripted_path.py) at ``~rtf`` times
real time, so its expectations are exact (recording_compare.test). The topic
variant (landmark_saver) and the service variant (record_server + record_client)
record the same sampling publisher at once; vision is lost mid-cycle. Checks the
sample stream against the core sampling rule (core/segment.SamplingSchedule), the
files against the truth and each other, the storage and recorded-path topics,
refusals of bad commands, and that the yaml-cpp reader (landmark_info) reads the
numbers PyYAML reads. This node is the mission's owner (the sampling publisher's
~mission_owner): vision loss is the mission state moving from recording to
rotating, which ends the recording. (A saver killed mid-mission:
recording_fake_turtlebot.test.)
"""
import math
import os
import shutil
import sys
import threading
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry, Path
from rosgraph_msgs.msg import Clock

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, '..')]
from scripted_path import ASV, LSV, ScriptedPath  # noqa: E402

from blind_navigation import names
from blind_navigation.core.geometry import quaternion_from_yaw  # noqa: E402
from blind_navigation.core.segment import SamplingSchedule  # noqa: E402
from blind_navigation.core.store import load_landmarks  # noqa: E402
from blind_navigation.msg import StorageUsage, PathSample  # noqa: E402
from blind_navigation.srv import RecordedSamples, RecordLandmark  # noqa: E402
from mission_owner import MissionOwner  # noqa: E402
from recording_tools import (WALL_TIMEOUT, Collector, landmark_info,  # noqa: E402
                             subscribers_of, wait_for)

SIM_BASE = 100.0            # sim time when the clock starts (non-zero: rospy treats 0 as unset)
PREROLL = 2.0               # s standing still before the path starts
CLOCK_STEP = 0.01           # s of sim time per /clock message
ODOM_PERIOD = 0.02          # s, 50 Hz like kobuki_node
#: Straight 6 s, a left arc of 8 s (~44 deg), straight 6 s: scripted_path.STRAIGHT_ARC_STRAIGHT
#: at half its length (each period, both switches; half the sim time of the run).
PATH = ((6.0, LSV, 0.0), (8.0, LSV, ASV), (6.0, LSV, 0.0))
VISION_LOST_AT = 19.5       # s into the path: mid-cycle of the last straight
BAD_SAMPLES_AT = 4.0        # s into the path: on the first straight
#: A tick fires on the first /clock at or after its time and reads the latest
#: odometry: periods and yaws may be late by a clock step plus scheduling delay.
#: Scheduling delay under a loaded 2-core machine, in sim time at rtf 2: < 0.1 s.
TICK_JITTER = 0.1
STRAIGHT_T, CURVED_T = 2.0, 1.0


class SimWorld(object):
    """Publishes /clock and /odom for the scripted path; runs events at sim times."""

    def __init__(self, path, rtf):
        self.path, self.rtf = path, rtf
        self.clock_pub = rospy.Publisher('/clock', Clock, queue_size=10)
        self.odom_pub = rospy.Publisher('/odom', Odometry, queue_size=50)
        self.t = 0.0                    # s since the clock started

    def path_time(self):
        return self.t - PREROLL


    def odometry(self):
        state = self.path.state(self.path_time())
        msg = Odometry()
        msg.header.stamp = rospy.Time.from_sec(SIM_BASE + self.t)
        msg.header.frame_id, msg.child_frame_id = 'odom', 'base_footprint'
        msg.pose.pose.position.x, msg.pose.pose.position.y = state.x, state.y
        q = msg.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(state.yaw)
        msg.twist.twist.linear.x, msg.twist.twist.angular.z = state.v, state.w
        return msg

    def publish_now(self):
        """/clock and /odom at the current time, without advancing it."""
        self.clock_pub.publish(Clock(clock=rospy.Time.from_sec(SIM_BASE + self.t)))
        self.odom_pub.publish(self.odometry())

    def run_until(self, path_time, events=()):
        """Advance sim time to ``path_time`` s into the path, firing ``events``
        [(path time, callable)] when reached."""
        events = sorted(events, key=lambda event: event[0])
        start_wall, start_t = time.monotonic(), self.t
        steps_per_odom = int(round(ODOM_PERIOD / CLOCK_STEP))
        step = int(round(self.t / CLOCK_STEP))
        while self.path_time() < path_time and not rospy.is_shutdown():
            step += 1
            self.t = step * CLOCK_STEP
            lag = start_wall + (self.t - start_t) / self.rtf - time.monotonic()
            if lag > 0:
                time.sleep(lag)
            self.clock_pub.publish(Clock(clock=rospy.Time.from_sec(SIM_BASE + self.t)))
            if step % steps_per_odom == 0:
                self.odom_pub.publish(self.odometry())
            while events and self.path_time() >= events[0][0]:
                events.pop(0)[1]()


class RecordingTestBase(unittest.TestCase):
    """Runs the scenario once (setUpClass); the test methods check its results."""

    expected_subscribers = ()

    @classmethod
    def setUpClass(cls):
        cls.path = ScriptedPath(PATH)
        cls.world = SimWorld(cls.path, rospy.get_param('~rtf', 2.0))
        cls.samples = Collector(names.SAMPLE, PathSample)
        cls.storage_msgs = Collector(names.STORAGE, StorageUsage)
        cls.paths = Collector(names.RECORDED_PATH, Path)
        # /odom first: a recorder takes the samples only once it has odometry (docs/recording.md,
        # "Ready"), so the world's first state goes out before the samples' subscribers are awaited
        odom_nodes = dict(cls.expected_subscribers).get('/odom', ())
        wait_for(lambda: set(odom_nodes) <= subscribers_of('/odom')
                 and cls.world.odom_pub.get_num_connections() >= len(odom_nodes),
                 '%s not all subscribed and connected to /odom' % ', '.join(odom_nodes))
        cls.world.publish_now()
        for topic, nodes in cls.expected_subscribers:
            wait_for(lambda: set(nodes) <= subscribers_of(topic),
                     '%s not all subscribed to %s' % (', '.join(nodes), topic))
        wait_for(lambda: cls.samples.sub.get_num_connections() > 0,
                 'the sampling publisher never connected to %s' % names.SAMPLE)
        cls.run_scenario()

    @classmethod
    def tearDownClass(cls):
        directory = os.path.dirname(rospy.get_param('~topic_file'))
        if directory.endswith('-recording-test'):       # only the launch's private directory
            shutil.rmtree(directory, ignore_errors=True)

    @classmethod
    def wait_for_storage_msgs(cls, count, message):
        wait_for(lambda: len(cls.storage_msgs.snapshot()) >= count, message)


class CompareTest(RecordingTestBase):
    """Topic and service variants side by side, vision lost mid-cycle."""

    expected_subscribers = ((names.SAMPLE, ('/landmark_saver', '/record_client')),
                            ('/odom', ('/landmark_saver', '/record_server', '/sampling_publisher')))

    @classmethod
    def run_scenario(cls):
        cls.bad_sample_pub = rospy.Publisher(names.SAMPLE, PathSample, queue_size=1)
        wait_for(lambda: cls.bad_sample_pub.get_num_connections() >= 3,
                 'the saver, the record client and this test are not all connected to %s'
                 % names.SAMPLE)
        owner = MissionOwner('/sampling_publisher')
        owner.publish('recording')
        owner.wait_heard(1, WALL_TIMEOUT)
        bad_samples = threading.Thread(target=cls.send_bad_samples)   # not blocking the clock
        events = [(BAD_SAMPLES_AT, bad_samples.start),
                  (VISION_LOST_AT, lambda: owner.publish('rotating'))]
        cls.world.run_until(VISION_LOST_AT + 2.0, events)
        bad_samples.join(WALL_TIMEOUT)
        samples = cls.samples.snapshot()
        cls.wait_for_storage_msgs(2 * sum(s.command in ('sample', 'final') for s in samples),
                                'not every sample was saved by both variants')
        cls.files = {variant: load_landmarks(rospy.get_param('~%s_file' % variant))
                     for variant in ('topic', 'service')}
        cls.vision_lost_t = SIM_BASE + PREROLL + VISION_LOST_AT

    @classmethod
    def send_bad_samples(cls):
        """A sample with an unknown command, on the topic and to the service, and a
        zero period to the service: all refused, nothing saved."""
        bad = PathSample(command='bogus', yaw=0.0, period=2.0)
        cls.bad_sample_pub.publish(bad)
        cls.bad_response = rospy.ServiceProxy(names.RECORD_LANDMARK, RecordLandmark)(
            command=bad.command, yaw=bad.yaw, period=bad.period)
        cls.bad_response_period = rospy.ServiceProxy(names.RECORD_LANDMARK, RecordLandmark)(
            command='sample', yaw=0.0, period=0.0)

    def ticks(self):
        samples = [s for s in self.samples.snapshot() if s.command == 'sample']
        finals = [s for s in self.samples.snapshot() if s.command == 'final']
        return samples, finals

    def test_sample_stream_follows_the_core_model(self):
        # The core sampling rule (core/segment.SamplingSchedule, as test/unit/unicycle.record_path
        # runs it) on the scripted truth, sample by sample: each tick comes its period after
        # the previous one, reads the true yaw, and the next period is the core classifier's
        # on the yaws read. A tick may be late by TICK_JITTER (scheduling), so the yaw it
        # reads may be that much later, and where the arc begins the rule may then switch
        # one tick earlier than on an ideal clock: checked against the rule on what was read.
        samples, finals = self.ticks()
        self.assertEqual(len(finals), 1, 'expected exactly one final sample')
        stamps = [s.header.stamp.to_sec() for s in samples]
        start = stamps[0] - samples[0].period            # the publisher's start tick
        schedule = SamplingSchedule(STRAIGHT_T, CURVED_T)
        schedule.update(self.path.state(start - SIM_BASE - PREROLL).yaw)   # the start yaw
        expected, previous = schedule.period, start
        for index, sample in enumerate(samples):
            where = 'tick %d at %.2f s' % (index + 1, sample.header.stamp.to_sec() - start)
            stamp = sample.header.stamp.to_sec()
            self.assertEqual(sample.period, expected, '%s: not the core classifier\'s period' % where)
            self.assertAlmostEqual(stamp - previous, sample.period, delta=TICK_JITTER, msg=where)
            truth = self.path.state(stamp - SIM_BASE - PREROLL)
            self.assertAlmostEqual(sample.yaw, truth.yaw, delta=ASV * TICK_JITTER, msg=where)
            expected, previous = schedule.update(sample.yaw), stamp
        self.assertEqual(set(s.period for s in samples), {STRAIGHT_T, CURVED_T})
        final = finals[0]
        self.assertAlmostEqual(final.header.stamp.to_sec(), self.vision_lost_t, delta=TICK_JITTER)
        self.assertAlmostEqual(final.period, final.header.stamp.to_sec() - stamps[-1], places=6)
        self.assertLessEqual(final.period, expected + TICK_JITTER, 'the final sample is a partial cycle')

    def test_periods_in_the_file_are_the_configured_ones_and_follow_the_curve(self):
        samples, finals = self.ticks()
        for variant, loaded in self.files.items():
            periods = [lm.T for lm in loaded.landmarks]
            self.assertEqual(periods[:-1], [s.period for s in samples], variant)
            # the file keeps six significant digits (core/store.format_number)
            self.assertAlmostEqual(periods[-1], finals[0].period, delta=5e-6 * finals[0].period,
                                   msg=variant)
            runs = [periods[0]]
            for period in periods[1:-1]:
                if period != runs[-1]:
                    runs.append(period)
            self.assertEqual(runs, [STRAIGHT_T, CURVED_T, STRAIGHT_T], variant)

    def test_landmarks_match_the_scripted_odometry(self):
        samples, finals = self.ticks()
        stamps = [s.header.stamp.to_sec() for s in samples + finals]
        for variant, loaded in self.files.items():
            self.assertEqual(len(loaded.landmarks), len(stamps), variant)
            self.assertEqual(loaded.warnings, [], variant)
            for stamp, sample, landmark in zip(stamps, samples + finals, loaded.landmarks):
                truth = self.path.state(stamp - SIM_BASE - PREROLL)
                self.assertAlmostEqual(landmark.psi, sample.yaw, delta=1e-5)
                if not self.near_segment_change(stamp):
                    self.assertAlmostEqual(landmark.v, truth.v, delta=1e-6)
                    self.assertAlmostEqual(landmark.w, truth.w, delta=1e-6)
            # d sums to the chords between the true positions at the ticks, from
            # the start (the first odometry, standing still at the origin); each
            # landmark's odometry may be late by up to a tick's jitter.
            points = [self.path.state(0.0)] + [self.path.state(stamp - SIM_BASE - PREROLL)
                                               for stamp in stamps]
            chords = sum(math.hypot(b.x - a.x, b.y - a.y) for a, b in zip(points, points[1:]))
            self.assertAlmostEqual(loaded.total_distance, chords,
                                   delta=LSV * (TICK_JITTER + ODOM_PERIOD), msg=variant)

    def near_segment_change(self, stamp):
        t = stamp - SIM_BASE - PREROLL
        changes = [start for start, _, _, _ in self.path.starts] + [self.path.duration]
        return any(abs(t - change) <= TICK_JITTER for change in changes)

    def test_topic_and_service_variants_record_the_same_landmarks(self):
        topic, service = self.files['topic'].landmarks, self.files['service'].landmarks
        self.assertEqual(len(topic), len(service))
        # Both read the same odometry stream for the same sample; they may pick
        # odometry one or two messages apart at each end of a landmark.
        tolerance_d = 2 * 2 * LSV * ODOM_PERIOD + 1e-5
        for index, (a, b) in enumerate(zip(topic, service)):
            self.assertEqual((a.T, a.psi), (b.T, b.psi), 'landmark %d' % (index + 1))
            self.assertAlmostEqual(a.d, b.d, delta=tolerance_d, msg='landmark %d' % (index + 1))
            self.assertAlmostEqual(a.v, b.v, delta=1e-6, msg='landmark %d' % (index + 1))
            self.assertAlmostEqual(a.w, b.w, delta=ASV + 1e-6, msg='landmark %d' % (index + 1))
        self.assertAlmostEqual(sum(a.d for a in topic), sum(b.d for b in service),
                               delta=tolerance_d)

    def test_unknown_command_and_bad_period_are_refused(self):
        self.assertFalse(self.bad_response.saved)
        self.assertIn('unknown command', self.bad_response.message)
        self.assertFalse(self.bad_response_period.saved)
        self.assertIn('T must be positive', self.bad_response_period.message)

    def test_storage_topic_matches_the_files(self):
        by_file = {}
        for msg in self.storage_msgs.snapshot():
            by_file[os.path.realpath(msg.file)] = msg
        self.assertEqual(len(by_file), 2, 'expected storage_msgs from both variants')
        for variant, loaded in self.files.items():
            last = by_file.get(os.path.realpath(loaded.path))
            self.assertIsNotNone(last, '%s: no storage names %s (got %s)'
                                 % (variant, os.path.realpath(loaded.path), sorted(by_file)))
            self.assertEqual(last.landmarks, len(loaded.landmarks), variant)
            self.assertEqual(last.bytes, os.path.getsize(loaded.path), variant)
            self.assertAlmostEqual(last.distance, loaded.total_distance, delta=1e-4)
            self.assertAlmostEqual(last.bytes_per_metre, last.bytes / last.distance, places=6)

    def test_the_sample_log_keeps_only_what_a_restarted_saver_needs(self):
        final = [s for s in self.samples.snapshot() if s.command == 'final'][0]
        by_file = {os.path.realpath(msg.file): msg for msg in self.storage_msgs.snapshot()}
        topic = by_file[os.path.realpath(self.files['topic'].path)]
        self.assertEqual((topic.recording, topic.sample), (final.recording, final.seq),
                         'the saver does not confirm its last sample')
        service = by_file[os.path.realpath(self.files['service'].path)]
        self.assertEqual(service.sample, 0, 'the service recorder has no sample numbers')
        ask = rospy.ServiceProxy(names.RECORDED_SAMPLES, RecordedSamples)
        early = ask(recording=final.recording, after=1)
        self.assertEqual(len(early.samples), 0)
        self.assertIn('sample 1 is not kept (%d to %d are)' % (final.seq, final.seq), early.message)
        last = ask(recording=final.recording, after=final.seq)
        self.assertEqual([sample.seq for sample in last.samples], [final.seq], last.message)

    def test_recorded_path_has_the_start_and_every_landmark(self):
        paths = self.paths.snapshot()
        self.assertTrue(paths, 'no nav_msgs/Path on %s' % names.RECORDED_PATH)
        longest = max(len(p.poses) for p in paths)
        self.assertEqual(longest, len(self.files['topic'].landmarks) + 1)
        self.assertEqual(paths[-1].header.frame_id, 'odom')

    def test_mission_files_are_new_time_stamped_files_behind_the_symlink(self):
        for variant in ('topic', 'service'):
            link = rospy.get_param('~%s_file' % variant)
            self.assertTrue(os.path.islink(link), link)
            target = os.path.realpath(link)
            self.assertEqual(os.path.dirname(target), os.path.dirname(link))
            self.assertRegex(os.path.basename(target), r'-\d{8}-\d{6}(-\d+)?\.yaml$')
            self.assertEqual(self.files[variant].metadata['recorder'], variant)

    def test_yaml_cpp_reader_reads_what_pyyaml_reads(self):
        for variant, loaded in self.files.items():
            info = landmark_info(loaded.path)
            self.assertEqual(info['landmarks'], len(loaded.landmarks))
            self.assertEqual(list(info['data']), loaded.labels)
            self.assertEqual([tuple(values) for values in info['data'].values()],
                             [tuple(lm) for lm in loaded.landmarks], variant)
            self.assertAlmostEqual(info['distance_m'], loaded.total_distance, places=9)
            self.assertAlmostEqual(info['duration_s'], sum(lm.T for lm in loaded.landmarks), places=9)
            self.assertEqual(info['bytes'], os.path.getsize(loaded.path))


if __name__ == '__main__':
    rospy.init_node('test_recording')
    rostest.rosrun('blind_navigation', 'recording_compare', CompareTest)

"""Test cases of interfaces.test (test_interfaces.py runs them): ros/odometry.OdometryFeed loses no message when its receive thread falls
behind (a loaded host; sim time at 10x) and takes each message as it arrives.

rospy reads a subscription's socket in chunks of up to 64 KiB and, with a queue
size, keeps only the newest that many messages of a chunk. Here a listener holds
the feed's receive thread while BURST odometry messages 0.02 s apart are published
(they wait in the socket), then lets it go: the feed's history must hold every
stamp, with no hole for state_at (the odometry at a sampling tick) to fall into.
An odometry reset is carried across in the old frame, or loses the frame.
"""
import math
import threading
import time
import unittest

import rospy
from nav_msgs.msg import Odometry

import waiting
from blind_navigation.ros.odometry import OdometryFeed

TOPIC = '/odometry_feed_test/odom'
BURST = 300          # messages (about 200 KiB: three of rospy's read chunks)
PERIOD = 0.02        # s between the messages' stamps (50 Hz odometry)
WAIT = 20.0          # s (wall) for each step


def unguarded(callback):
    """The feeds' guard here: an exception in a callback is the test's to see."""
    return callback


def odometry(stamp):
    msg = Odometry()
    msg.header.stamp = rospy.Time.from_sec(stamp)
    msg.header.frame_id, msg.child_frame_id = 'odom', 'base_footprint'
    msg.pose.pose.orientation.w = 1.0
    return msg


class OdometryFeedBurstTest(unittest.TestCase):

    def test_a_burst_behind_a_busy_receive_thread_is_kept_whole(self):
        feed = OdometryFeed(TOPIC, unguarded)
        held, release = threading.Event(), threading.Event()

        def hold_the_first(state):
            if not held.is_set():
                held.set()
                release.wait(WAIT)
        feed.add_listener(hold_the_first)
        stamps = []                 # every state the feed accepted, as its listeners see them
        feed.add_listener(lambda state: stamps.append(state.stamp))
        feed.acquire('test')
        publisher = rospy.Publisher(TOPIC, Odometry, queue_size=None)   # synchronous: none dropped here
        waiting.wait_for(lambda: publisher.get_num_connections() == 1, 'the feed never connected', WAIT)
        start = 1000.0
        publisher.publish(odometry(start))
        self.assertTrue(held.wait(WAIT), 'the feed never received the first message')
        sender = threading.Thread(target=lambda: [publisher.publish(odometry(start + i * PERIOD))
                                                  for i in range(1, BURST + 1)], daemon=True)
        sender.start()
        time.sleep(1.0)               # the burst fills the socket while the receive thread is held
        release.set()
        sender.join(WAIT)
        self.assertFalse(sender.is_alive(), 'the burst was never sent')
        last = start + BURST * PERIOD
        waiting.wait_for(lambda: feed.latest() is not None and feed.latest().stamp >= last - 1e-6,
                         'the feed never read the burst to its end', WAIT)
        gaps = [round(b - a, 3) for a, b in zip(stamps, stamps[1:]) if b - a > 1.5 * PERIOD]
        self.assertEqual(len(stamps), BURST + 1, 'messages lost; gaps between stamps: %s' % gaps)
        self.assertEqual(feed.refused, 0)


class OdometryFeedTakeTest(unittest.TestCase):
    """Each message is taken as it arrives, with no reader; a reader waiting for a
    stamp (state_at(stamp, wait)) gets it when it arrives."""

    @classmethod
    def setUpClass(cls):
        cls.feed = OdometryFeed(TOPIC + '_taken', unguarded)
        cls.feed.acquire('recorder')
        cls.publisher = rospy.Publisher(TOPIC + '_taken', Odometry, queue_size=None)
        waiting.wait_for(lambda: cls.publisher.get_num_connections() == 1,
                         'the feed never connected', WAIT)
        cls.stamp = 2000.0

    def publish(self):
        type(self).stamp += PERIOD
        self.publisher.publish(odometry(self.stamp))
        return self.stamp

    def taken(self):
        """The newest state taken."""
        latest = self.feed.latest()
        return None if latest is None else round(latest.stamp, 6)

    def test_1_every_message_is_taken_as_it_arrives(self):
        for _ in range(3):
            last = self.publish()
            waiting.wait_for(lambda: self.taken() == round(last, 6),
                             'message %.2f was not taken without a reader' % last, WAIT)
        self.assertEqual(self.feed.refused, 0)

    def test_2_a_stamp_waited_for_is_returned_as_it_arrives(self):
        result = []
        target = self.stamp + PERIOD / 2     # the next message's stamp, clear of rounding
        reader = threading.Thread(target=lambda: result.append(self.feed.state_at(target, WAIT)))
        reader.start()
        waiting.wait_for(lambda: self.feed._waiting == 1, 'the reader never waited', WAIT)
        last = self.publish()
        reader.join(WAIT)
        self.assertFalse(reader.is_alive(), 'state_at(wait=) did not return')
        self.assertEqual([round(state.stamp, 6) for state in result], [round(last - PERIOD, 6)],
                         'state_at(stamp) is not the last state at or before the stamp')
        self.assertEqual(self.taken(), round(last, 6))


def moving(stamp, x, y, yaw, v):
    """An odometry message at ``stamp`` of a robot at (x, y, yaw) driving straight at ``v``."""
    msg = odometry(stamp)
    msg.pose.pose.position.x, msg.pose.pose.position.y = x, y
    msg.pose.pose.orientation.z, msg.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    msg.twist.twist.linear.x = v
    return msg


class OdometryFeedResetTest(unittest.TestCase):
    """An odometry reset (kobuki_node's: pose and heading from zero, twist going on) while
    a robot drives straight at V: carried across in the old frame when odometry went on
    at 50 Hz; the frame lost (never fresh again while held) after a 2 s silence."""

    V, YAW = 0.3, 0.5

    def drive(self, topic, silence):
        feed = OdometryFeed(topic, unguarded)
        resets, stamps, received = [], [], []
        feed.add_listener(received.append, raw=True)
        feed.on_reanchor(lambda reason, trusted: resets.append((reason, trusted)))
        feed.add_listener(lambda state: stamps.append(state.stamp))
        feed.acquire('driver')
        publisher = rospy.Publisher(topic, Odometry, queue_size=None)
        waiting.wait_for(lambda: publisher.get_num_connections() == 1, 'the feed never connected', WAIT)
        start, c, s = 3000.0, math.cos(self.YAW), math.sin(self.YAW)
        for i in range(150):                            # 3 s from (1, 1) along YAW
            t = i * PERIOD
            publisher.publish(moving(start + t, 1.0 + c * self.V * t, 1.0 + s * self.V * t,
                                     self.YAW, self.V))
        reset_at = start + 150 * PERIOD + silence
        for i in range(100):                            # 2 s from the origin along 0
            t = i * PERIOD
            publisher.publish(moving(reset_at + t, self.V * t, 0.0, 0.0, self.V))
        last = reset_at + 99 * PERIOD
        waiting.wait_for(lambda: len(received) >= 250, 'the feed never received the stream', WAIT)
        return feed, resets, stamps, last

    def test_a_reset_while_driving_is_carried_across_in_the_old_frame(self):
        feed, resets, stamps, last = self.drive(TOPIC + '_reset', 0.0)
        waiting.wait_for(lambda: feed.latest() is not None and feed.latest().stamp >= last - 1e-6,
                         'the feed never took the stream after the reset', WAIT)
        self.assertEqual([trusted for _, trusted in resets], [True], resets)
        self.assertIn('odometry reset re-anchored', resets[0][0])
        latest, t = feed.latest(), last - 3000.0
        self.assertAlmostEqual(latest.x, 1.0 + math.cos(self.YAW) * self.V * t, delta=0.01)
        self.assertAlmostEqual(latest.y, 1.0 + math.sin(self.YAW) * self.V * t, delta=0.01)
        self.assertAlmostEqual(latest.yaw, self.YAW, delta=0.01)
        self.assertEqual(len(stamps), 250, 'every state once, the confirming second too')
        self.assertIsNotNone(feed.fresh(5.0))
        self.assertIsNone(feed.lost)
        feed.release('driver')

    def test_a_reset_after_a_silence_loses_the_frame(self):
        feed, resets, _, _ = self.drive(TOPIC + '_reset_silent', 2.0)
        waiting.wait_for(lambda: resets, 'the feed never reported the reset', WAIT)
        self.assertEqual([trusted for _, trusted in resets], [False], resets)
        self.assertTrue(feed.lost.startswith('odometry reset not re-anchored'), feed.lost)
        self.assertIsNone(feed.fresh(5.0), 'never fresh once the frame is lost')
        self.assertIn('odometry reset not re-anchored', feed.describe_missing(5.0))
        feed.release('driver')
        self.assertIsNone(feed.lost, 'the next holder starts on the frame it finds')


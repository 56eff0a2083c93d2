#!/usr/bin/env python3
"""rostest: ros/odometry.OdometryFeed loses no message when its receive thread falls
behind (a loaded host; sim time at 10x), and takes messages in batches only while
every holder reads back (batched), with readers catching up on the rest.

rospy reads a subscription's socket in chunks of up to 64 KiB and, with a queue
size, keeps only the newest that many messages of a chunk. Here a listener holds
the feed's receive thread while BURST odometry messages 0.02 s apart are published
(they wait in the socket), then lets it go: the feed's history must hold every
stamp, with no hole for state_at (the odometry at a sampling tick) to fall into.
"""
import threading
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

import waiting
from blind_navigation.ros.odometry import BATCH, OdometryFeed

TOPIC = '/odometry_feed_test/odom'
BURST = 300          # messages (about 200 KiB: three of rospy's read chunks)
PERIOD = 0.02        # s between the messages' stamps (50 Hz odometry)
WAIT = 20.0          # s (wall) for each step


def odometry(stamp):
    msg = Odometry()
    msg.header.stamp = rospy.Time.from_sec(stamp)
    msg.header.frame_id, msg.child_frame_id = 'odom', 'base_footprint'
    msg.pose.pose.orientation.w = 1.0
    return msg


class OdometryFeedBurstTest(unittest.TestCase):

    def test_a_burst_behind_a_busy_receive_thread_is_kept_whole(self):
        feed = OdometryFeed(TOPIC)
        held, release = threading.Event(), threading.Event()

        def hold_the_first(state):
            if not held.is_set():
                held.set()
                release.wait(WAIT)
        feed.add_listener(hold_the_first)
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
        stamps = [state.stamp for state in feed.states_after(start - 1.0)]
        gaps = [round(b - a, 3) for a, b in zip(stamps, stamps[1:]) if b - a > 1.5 * PERIOD]
        self.assertEqual(len(stamps), BURST + 1, 'messages lost; gaps between stamps: %s' % gaps)
        self.assertEqual(feed.refused, 0)


class OdometryFeedBatchTest(unittest.TestCase):
    """Batching (module docstring of ros/odometry.py): while every holder is batched,
    messages wait for BATCH of them or for a reader; a driving holder turns it off."""

    @classmethod
    def setUpClass(cls):
        cls.feed = OdometryFeed(TOPIC + '_batched')
        cls.feed.acquire('recorder', batched=True)
        cls.publisher = rospy.Publisher(TOPIC + '_batched', Odometry, queue_size=None)
        waiting.wait_for(lambda: cls.publisher.get_num_connections() == 1,
                         'the feed never connected', WAIT)
        cls.stamp = 2000.0
        cls.received = 0

    def publish(self, count):
        """Publish ``count`` messages PERIOD apart; wait until the feed received them
        (taken or pending). Returns the last stamp."""
        for _ in range(count):
            self.stamp += PERIOD
            self.publisher.publish(odometry(self.stamp))
        type(self).stamp = self.stamp
        type(self).received += count
        waiting.wait_for(lambda: self.feed._arrived >= self.received,
                         'the feed never received message %d' % self.received, WAIT)
        return self.stamp

    def newest(self):
        latest = self.feed.latest()
        return None if latest is None else round(latest.stamp, 6)

    def test_1_fewer_than_a_batch_wait_and_a_reader_catches_up_at_the_next_message(self):
        self.assertTrue(self.feed.batched)
        first = self.publish(1)
        self.publish(BATCH - 2)
        self.assertEqual(self.feed.pending, BATCH - 1)
        self.assertIsNone(self.feed.latest(), 'a message was taken before its batch was full')
        result = []
        reader = threading.Thread(target=lambda: result.append(self.feed.catch_up(WAIT)))
        reader.start()
        waiting.wait_for(lambda: self.feed._waiting == 1, 'the reader never waited', WAIT)
        last = self.publish(1)
        reader.join(WAIT)
        self.assertEqual(result, [True], 'catch_up did not return True at the next message')
        self.assertEqual(self.newest(), round(last, 6))
        self.assertEqual(self.feed.pending, 0)
        stamps = [state.stamp for state in self.feed.states_after(first - 1.0)]
        self.assertEqual(len(stamps), BATCH)
        self.assertEqual(stamps, sorted(stamps), 'taken out of order')

    def test_2_a_full_batch_is_taken_without_a_reader(self):
        last = self.publish(BATCH)
        waiting.wait_for(lambda: self.newest() == round(last, 6),
                         'a full batch was not taken', WAIT)
        self.assertEqual(self.feed.pending, 0)

    def test_3_catch_up_without_a_next_message_gives_up_and_keeps_what_was_taken(self):
        before = self.newest()
        self.publish(1)
        started = time.monotonic()
        self.assertFalse(self.feed.catch_up(0.3))
        self.assertGreaterEqual(time.monotonic() - started, 0.3)
        self.assertEqual(self.newest(), before)
        self.assertEqual(self.feed.pending, 1)

    def test_4_a_stamp_waited_for_is_taken_as_it_arrives(self):
        self.publish(1)      # pending (test 3 left one too)
        result = []
        target = self.stamp + PERIOD / 2     # the next message's stamp, clear of rounding
        reader = threading.Thread(target=lambda: result.append(self.feed.wait_for_stamp(target, WAIT)))
        reader.start()
        waiting.wait_for(lambda: self.feed._waiting == 1, 'the reader never waited', WAIT)
        last = self.publish(1)
        reader.join(WAIT)
        self.assertEqual(result, [True])
        self.assertEqual(self.newest(), round(last, 6))
        self.assertEqual(self.feed.pending, 0)

    def test_5_a_driving_holder_turns_batching_off_until_it_releases(self):
        self.feed.acquire('driver')
        try:
            self.assertFalse(self.feed.batched)
            for _ in range(3):
                last = self.publish(1)
                waiting.wait_for(lambda: self.newest() == round(last, 6),
                                 'a message was not taken at once with a driving holder', WAIT)
        finally:
            self.feed.release('driver')
        self.assertTrue(self.feed.batched)
        self.publish(1)
        self.assertEqual(self.feed.pending, 1)
        self.assertEqual(self.feed.refused, 0)


if __name__ == '__main__':
    rospy.init_node('test_odometry_feed')
    rostest.rosrun('blind_navigation', 'odometry_feed', '__main__')   # both test classes

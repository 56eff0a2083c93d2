#!/usr/bin/env python3
"""rostest: ros/odometry.OdometryFeed loses no message when its receive thread falls
behind (a loaded host; sim time at 10x).

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
from blind_navigation.ros.odometry import OdometryFeed

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


if __name__ == '__main__':
    rospy.init_node('test_odometry_feed')
    rostest.rosrun('blind_navigation', 'odometry_feed', OdometryFeedBurstTest)

#!/usr/bin/env python3
"""rostest: blind_navigation/subscription_watchdog.py reconnects a subscription to a
publisher the master lists but the node has no connection to (what a missed
publisherUpdate leaves), and reports nothing while every publisher is connected."""
import os
import subprocess
import time
import unittest

import rosgraph
import rospy
import rostest
from std_msgs.msg import String

import waiting
from blind_navigation.ros import subscription_watchdog

TOPIC = '/watchdog_test'


class SubscriptionWatchdogTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_subscription_watchdog')
        cls.talker = subprocess.Popen(['rostopic', 'pub', '-r', '20', TOPIC, 'std_msgs/String',
                                       'data: hi', '__name:=watchdog_talker'],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      env=dict(os.environ))
        cls.received = []
        rospy.Subscriber(TOPIC, String, cls.received.append)
        cls.master = rosgraph.Master(rospy.get_name())
        cls.registration = subscription_watchdog._registration_manager()
        waiting.wait_for(lambda: cls.received, 'a first message from the talker')

    @classmethod
    def tearDownClass(cls):
        cls.talker.terminate()
        cls.talker.wait(10)

    def messages_within(self, seconds):
        count = len(self.received)
        time.sleep(seconds)
        return len(self.received) - count

    def test_a_lost_connection_is_found_and_healed(self):
        self.assertIsNotNone(self.registration, 'rospy RegManager not found')
        self.assertEqual(subscription_watchdog.heal_once(self.master, self.registration), [],
                         'a connected publisher was reported missing')
        impl = subscription_watchdog.get_topic_manager().get_subscriber_impl(TOPIC)
        for connection in list(impl.connections):       # what a missed registration leaves
            impl.remove_connection(connection)
            connection.close()
        self.assertEqual(self.messages_within(0.5), 0, 'messages still arrive after the drop')
        missing = subscription_watchdog.heal_once(self.master, self.registration)
        self.assertEqual([topic for topic, _ in missing], [TOPIC])
        waiting.wait_for(lambda: self.messages_within(0.5) > 0, 'messages again after healing',
                         timeout=10.0)


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'subscription_watchdog', SubscriptionWatchdogTest)

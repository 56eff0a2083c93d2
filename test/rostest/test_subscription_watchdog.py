"""Test case of interfaces.test (test_interfaces.py runs it): ros/common.py's watchdog reconnects a subscription to a publisher
the master lists but the node has no connection to (what a missed publisherUpdate
leaves), and reports nothing while every publisher is connected. The product uses
rospy's public API only; this test drops the connection through rospy's topic
manager (its internals) to make the state a missed registration leaves."""
import os
import subprocess
import time
import unittest
import xmlrpc.client

import rosgraph
import rospy
from rospy.impl.registration import get_topic_manager
from std_msgs.msg import String

import waiting
from blind_navigation.ros.common import heal_once

TOPIC = '/watchdog_test'


class SubscriptionWatchdogTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.talker = subprocess.Popen(['rostopic', 'pub', '-r', '20', TOPIC, 'std_msgs/String',
                                       'data: hi', '__name:=watchdog_talker'],
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      env=dict(os.environ))
        cls.received = []
        cls.subscriber = rospy.Subscriber(TOPIC, String, cls.received.append)
        cls.master = rosgraph.Master(rospy.get_name())
        cls.node = xmlrpc.client.ServerProxy(rospy.get_node_uri())
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
        self.assertEqual(heal_once(self.master, self.node, [self.subscriber]), [],
                         'a connected publisher was reported missing')
        impl = get_topic_manager().get_subscriber_impl(TOPIC)
        for connection in list(impl.connections):       # what a missed registration leaves
            impl.remove_connection(connection)
            connection.close()
        self.assertEqual(self.messages_within(0.5), 0, 'messages still arrive after the drop')
        self.assertEqual(self.subscriber.get_num_connections(), 0)
        healed = heal_once(self.master, self.node, [self.subscriber])
        self.assertEqual(healed, [TOPIC])
        waiting.wait_for(lambda: self.messages_within(0.5) > 0, 'messages again after healing',
                         timeout=10.0)


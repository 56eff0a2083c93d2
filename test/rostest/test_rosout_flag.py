#!/usr/bin/env python3
"""rostest: ros/common.cache_rosout_flag. rospy asks the master for the unset
/rosout_disable_topics_generation before every log line it sends to /rosout
(ros/ros_comm#2337); after cache_rosout_flag a log line asks the master nothing,
and a value set on the master later still reaches the process's cache."""
import unittest

import rosgraph
import rospy
import rostest
from rospy.impl.paramserver import get_param_server_cache

import waiting
from blind_navigation.ros.common import ROSOUT_TOPICS_FLAG, cache_rosout_flag


class CountingMaster(object):
    """Stands in for rospy's master proxy target: counts each call by name, then makes it."""

    def __init__(self, target):
        self.target = target
        self.calls = []

    def __getattr__(self, name):
        self.calls.append(name)
        return getattr(self.target, name)


class RosoutFlagTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_rosout_flag')
        rospy.loginfo('connecting /rosout')      # rospy's first log line sets up its publisher
        rospy.client._init_param_server()
        cls.proxy = rospy.client._param_server
        cls.master = CountingMaster(cls.proxy.target)
        cls.proxy.target = cls.master

    def log_lines(self, count):
        del self.master.calls[:]
        for line in range(count):
            rospy.loginfo('line %d', line)
        return list(self.master.calls)

    def test_1_unpatched_rospy_asks_the_master_at_every_line(self):
        # the reason for cache_rosout_flag: if this stops failing, rospy was fixed
        self.assertFalse(rospy.has_param(ROSOUT_TOPICS_FLAG), 'the test needs the flag unset')
        calls = self.log_lines(3)
        self.assertEqual(calls.count('subscribeParam'), 3, 'calls to the master: %r' % calls)

    def test_2_after_caching_a_log_line_asks_nothing(self):
        cache_rosout_flag()
        self.assertIs(rospy.get_param_cached(ROSOUT_TOPICS_FLAG), False)
        calls = self.log_lines(5)
        self.assertEqual(calls, [], 'log lines still called the master: %r' % calls)

    def test_3_a_value_set_later_still_arrives(self):
        cache_rosout_flag()
        other_node = rosgraph.Master('/rosout_flag_setter')    # not this process's rospy cache
        other_node.setParam(ROSOUT_TOPICS_FLAG, True)
        try:
            waiting.wait_for(lambda: get_param_server_cache().get(ROSOUT_TOPICS_FLAG) is True,
                             'the master to send the new value (paramUpdate)', timeout=10.0)
            self.assertEqual(self.log_lines(2), [])
        finally:
            other_node.deleteParam(ROSOUT_TOPICS_FLAG)


if __name__ == '__main__':
    rostest.rosrun('blind_navigation', 'rosout_flag', RosoutFlagTest)

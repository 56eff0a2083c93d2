#!/usr/bin/env python3
"""rostest: wrong wiring is refused (wiring.test). The layer in namespace wiring: its
odometry topic carries geometry_msgs/Twist, a Kobuki event topic and RTAB-Map's odom_info_lite carry
std_msgs/String (published once this node hears the layer's /rosout): each topic gives
exactly one FATAL line naming it, nav_msgs/Odometry (or the event's, OdomInfo's type)
and the type found, also after the watchdog's last master check (10 s); the mission
ends aborted naming the first fault found, and nothing but zero reaches cmd_vel, also after
vision_lost. The node then runs test_wiring_mid_mission.py's case on the root
namespace's layer."""
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Log
from std_msgs.msg import Empty, String

from recording_tools import Collector
from test_wiring_mid_mission import WiringMidMissionTest
from waiting import wait_for

from blind_navigation.msg import MissionStatus

NS = '/wiring'
LAYER = NS + '/blind_navigation'
ODOM = '/wiring_test/odom_is_twist'
BUMPER = NS + '/mobile_base/events/bumper'
ODOM_INFO = NS + '/rtabmap/odom_info_lite'
#: s (wall) after the wrong publishers appeared by which every check ran: the subscription
#: watchdog's last master check is 10 s after a subscription (ros/common.py)
SETTLE = 12.0


class WiringTest(unittest.TestCase):

    stop = None

    @classmethod
    def setUpClass(cls):
        if cls.stop is None:
            cls.start_wrong_wiring()

    @classmethod
    def start_wrong_wiring(cls):
        """The collectors, then (once this node hears the layer's /rosout) the wrong publishers."""
        cls.rosout = Collector('/rosout', Log)
        cls.states = Collector(LAYER + '/state', String)
        cls.commands = Collector(NS + '/cmd_vel_mux/input/teleop', Twist)
        # a FATAL line logged before this node hears the layer's /rosout would be lost
        wait_for(lambda: any(c.callerid_pub == LAYER for c in cls.rosout.sub.impl.connections),
                 "this node's /rosout subscription connected to %s" % LAYER, timeout=60.0)
        cls.started = time.monotonic()
        cls.wrong = [(rospy.Publisher(ODOM, Twist, queue_size=5), Twist(), 0.02),
                     (rospy.Publisher(BUMPER, String, queue_size=5), String(data='pressed'), 0.2),
                     (rospy.Publisher(ODOM_INFO, String, queue_size=5), String(data='lost'), 0.1)]
        cls.stop = threading.Event()
        threading.Thread(target=cls.publish_wrong, daemon=True).start()

    @classmethod
    def tearDownClass(cls):
        cls.stop.set()

    @classmethod
    def publish_wrong(cls):
        next_at = [0.0] * len(cls.wrong)
        while not cls.stop.is_set() and not rospy.is_shutdown():
            now = time.monotonic()
            for index, (publisher, msg, period) in enumerate(cls.wrong):
                if now >= next_at[index]:
                    publisher.publish(msg)
                    next_at[index] = now + period
            time.sleep(0.01)

    def fatal(self, topic):
        return [m.msg for m in self.rosout.snapshot()
                if m.level == Log.FATAL and m.name == LAYER and topic + ' ' in m.msg]

    def refused_once(self, topic, expected, found):
        wait_for(lambda: self.fatal(topic), 'a FATAL line naming %s' % topic, timeout=30.0)
        wait_for(lambda: time.monotonic() > self.started + SETTLE, 'the checks settle', SETTLE + 5)
        lines = self.fatal(topic)
        self.assertEqual(len(lines), 1, 'one FATAL line for %s, got %s' % (topic, lines))
        for text in (topic, expected, found):
            self.assertIn(text, lines[0])

    def test_odometry_of_another_type(self):
        self.refused_once(ODOM, 'nav_msgs/Odometry', 'geometry_msgs/Twist')
        wait_for(lambda: 'aborted' in [m.data for m in self.states.snapshot()],
                 'the mission aborted (states %s)' % [m.data for m in self.states.snapshot()])
        # three topics are wired wrong: whichever connection the layer checks first ends the
        # mission (the order is the master's and the scheduler's); the others are logged FATAL
        reasons = [m.msg for m in self.rosout.snapshot() if m.name == LAYER and '-> aborted' in m.msg]
        faults = ['wrong wiring: %s carries %s' % (topic, found) for topic, found in
                  ((ODOM, 'geometry_msgs/Twist'), (BUMPER, 'std_msgs/String'), (ODOM_INFO, 'std_msgs/String'))]
        self.assertTrue(reasons and any(fault in reasons[-1] for fault in faults),
                        'the abort names one of the faults %s: %s' % (faults, reasons))
        self.assertIn('[outcome WIRING (%d)]' % MissionStatus.OUTCOME_WIRING, reasons[-1])   # its code
        vision_lost = rospy.Publisher(LAYER + '/vision_lost', Empty, queue_size=1, latch=True)
        for _ in range(10):
            vision_lost.publish(Empty())
            time.sleep(0.3)
        states = [m.data for m in self.states.snapshot()]
        self.assertEqual(states[-1], 'aborted', 'vision_lost changes nothing: %s' % states)
        self.assertNotIn('rotating', states)
        moving = [(c.linear.x, c.angular.z) for c in self.commands.snapshot()
                  if c.linear.x != 0.0 or c.angular.z != 0.0]
        self.assertEqual(moving, [], 'no non-zero velocity command')

    def test_kobuki_event_of_another_type(self):
        self.refused_once(BUMPER, 'kobuki_msgs/BumperEvent', 'std_msgs/String')

    def test_odom_info_of_another_type(self):
        self.refused_once(ODOM_INFO, 'rtabmap_msgs/OdomInfo', 'std_msgs/String')


def both():
    """test_wiring_mid_mission.py's case, then this module's: the wrong publishers start
    first (__main__), so the watchdog's SETTLE runs out while the mid-mission case plays."""
    loader = unittest.TestLoader()
    return unittest.TestSuite(loader.loadTestsFromTestCase(case) for case in (WiringMidMissionTest, WiringTest))


if __name__ == '__main__':
    rospy.init_node('wiring_test')
    WiringTest.start_wrong_wiring()
    rostest.rosrun('blind_navigation', 'wiring', __name__ + '.both')

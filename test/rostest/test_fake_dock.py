#!/usr/bin/env python3
"""rostest: the fake TurtleBot's dock (dock:=start): IR and SensorState at 50 Hz with kobuki_msgs'
MD5 sums; dock_drive_action docks the robot after it drove off (succeeded, charger 6, the true
pose on the dock's contacts); a cancelled goal is preempted and the base stops."""
import math
import threading
import unittest

import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from nav_msgs.msg import Odometry

from blind_navigation.core.geometry import Pose2D, yaw_from_quaternion
from blind_navigation.ros import kobuki_msgs_compat as kobuki_msgs
from blind_navigation.ros.common import twist
from blind_navigation.ros.goal_client import GoalClient
from blind_navigation.sim.dock import CHARGING, DISCHARGING, Dock

import waiting

TIMEOUT = 20.0       # s of wall time for a wait
#: kobuki_msgs' MD5 sums (genmsg on kobuki_msgs' own files; test/unit/test_dock.py)
MD5 = {'kobuki_msgs/DockInfraRed': 'a3d77f7d15e50579473dcc24e9b97b34',
       'kobuki_msgs/SensorState': '430a4bfd78449c8740bfef32b26613a6'}
DOCK = Dock.behind(Pose2D(0.0, 0.0, 0.0))


class Latest(object):
    """The last message of a topic and how many came."""

    def __init__(self, topic, cls):
        self.lock, self.msg, self.count = threading.Lock(), None, 0
        self.sub = rospy.Subscriber(topic, cls, self.on_msg, queue_size=100)

    def on_msg(self, msg):
        with self.lock:
            self.msg, self.count = msg, self.count + 1


class FakeDockTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.core = Latest('/mobile_base/sensors/core', kobuki_msgs.SensorState)
        cls.ir = Latest('/mobile_base/sensors/dock_ir', kobuki_msgs.DockInfraRed)
        cls.truth = Latest('/ground_truth/odom', Odometry)
        cls.teleop = rospy.Publisher('/cmd_vel_mux/input/teleop', type(twist()), queue_size=10)
        cls.client = GoalClient('/dock_drive_action', kobuki_msgs.AutoDockingAction)
        waiting.wait_for(lambda: cls.client.wait_for_server(rospy.Duration(0.1)) or False,
                         'the dock_drive_action server', TIMEOUT)
        waiting.wait_for(lambda: cls.core.msg and cls.ir.msg and cls.truth.msg, 'core, dock_ir, ground truth',
                         TIMEOUT)

    def pose(self):
        p = self.truth.msg.pose.pose
        q = p.orientation
        return Pose2D(p.position.x, p.position.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))

    def drive(self, v, seconds):
        """Teleop at v m/s for ``seconds`` s of sim time, then zero."""
        end = rospy.get_time() + seconds
        while rospy.get_time() < end and not rospy.is_shutdown():
            self.teleop.publish(twist(v))
            rospy.sleep(0.05)
        self.teleop.publish(twist())

    def test_1_sensors_at_their_rates_with_kobuki_types(self):
        # the dock's IR at the Kobuki's 50 Hz; SensorState at the fake's 10 Hz (docs/fake_turtlebot.md)
        for topic, latest, hz in (('/mobile_base/sensors/core', self.core, 10.0),
                                  ('/mobile_base/sensors/dock_ir', self.ir, 50.0)):
            self.assertEqual(latest.sub.type, type(latest.msg)._type)
            self.assertEqual(type(latest.msg)._md5sum, MD5[latest.sub.type], topic)
            start, count = rospy.get_time(), latest.count
            rospy.sleep(2.0)
            rate = (latest.count - count) / (rospy.get_time() - start)
            self.assertTrue(0.9 * hz <= rate <= 1.1 * hz, '%s at %.1f Hz (%g expected)' % (topic, rate, hz))
        self.assertEqual(self.core.msg.charger, DISCHARGING)
        self.assertEqual(self.core.msg.battery, 165)        # the fake's full battery, 16.5 V
        # at the start the robot faces away from the dock: no receiver sees it
        self.assertEqual(list(bytearray(self.ir.msg.data)), [0, 0, 0])

    def test_2_drive_off_then_dock(self):
        self.drive(0.2, 3.0)
        self.assertGreater(DOCK.to_dock(self.pose().x, self.pose().y)[0], 0.7, 'drove off the dock')
        self.client.send_goal(kobuki_msgs.AutoDockingGoal())
        finished = self.client.wait_for_result(rospy.Duration(150.0))
        self.assertTrue(finished, 'no result within 150 s sim')
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED, self.client.get_goal_status_text())
        self.assertEqual(self.client.get_result().text, 'Arrived on docking station successfully.')
        rospy.sleep(0.2)
        self.assertEqual(self.core.msg.charger, CHARGING)
        pose, docked = self.pose(), DOCK.docked_pose()
        self.assertLess(math.hypot(pose.x - docked.x, pose.y - docked.y), 0.06, 'on the contacts: %s' % (pose,))

    def test_3_cancel_preempts_and_stops(self):
        self.drive(-0.2, 3.0)                   # docked, facing the dock: back off it
        self.assertEqual(self.core.msg.charger, DISCHARGING)
        self.client.send_goal(kobuki_msgs.AutoDockingGoal())
        rospy.sleep(2.0)
        self.client.cancel_goal()
        self.assertTrue(self.client.wait_for_result(rospy.Duration(5.0)), 'no result after cancel')
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED)
        rospy.sleep(1.0)
        speed = self.truth.msg.twist.twist
        self.assertLess(abs(speed.linear.x) + abs(speed.angular.z), 1e-3, 'the base stopped after the cancel')


if __name__ == '__main__':
    rospy.init_node('test_fake_dock')
    rostest.rosrun('blind_navigation', 'fake_dock', FakeDockTest)

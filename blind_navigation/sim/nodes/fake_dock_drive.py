#!/usr/bin/env python3
"""Fake Kobuki auto-docking node: the action ``dock_drive_action`` (kobuki_msgs/AutoDocking).

As kobuki_auto_docking: on a goal, sim/dock_drive.DockDrive runs once per
``mobile_base/sensors/dock_ir`` message on it, the latest ``mobile_base/sensors/core``
(bumper, charger) and ``odom`` heading, publishes its velocity straight to the base
(``mobile_base/commands/velocity``, past the mux) and its state as feedback; the goal
succeeds in DONE (on the charger); cancel or a new goal preempts it. The fake also aborts (sim/docking.verdict): dock not seen, dock lost, time limit,
with a zero velocity. Param ``~time_limit`` (s of sim time).
"""
import threading

import actionlib
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from blind_navigation.ros import kobuki_msgs_compat as kobuki_msgs
from blind_navigation.ros.common import subscribe, twist
from blind_navigation.core.geometry import yaw_from_quaternion
from blind_navigation.sim.dock_drive import DockDrive
from blind_navigation.sim.docking import TIME_LIMIT, verdict


class FakeDockDrive(object):
    """The action server (module docstring)."""

    def __init__(self):
        self.time_limit = float(rospy.get_param('~time_limit', TIME_LIMIT))
        self.lock = threading.Lock()
        self.drive, self.started, self.core, self.heading = None, None, None, None
        self.velocity = rospy.Publisher('mobile_base/commands/velocity', Twist, queue_size=10)
        self.server = actionlib.SimpleActionServer('dock_drive_action', kobuki_msgs.AutoDockingAction,
                                                   auto_start=False)
        self.server.register_goal_callback(self.on_goal)
        self.server.register_preempt_callback(self.on_preempt)
        subscribe('odom', Odometry, self.on_odom)
        subscribe('mobile_base/sensors/core', kobuki_msgs.SensorState, self.on_core)
        subscribe('mobile_base/sensors/dock_ir', kobuki_msgs.DockInfraRed, self.on_ir)
        self.server.start()

    def on_goal(self):
        self.server.accept_new_goal()
        with self.lock:
            self.drive, self.started = DockDrive(), rospy.get_time()
        rospy.loginfo('fake_dock_drive: new goal received and accepted')

    def on_preempt(self):
        """Cancel, or a new goal (it preempts the running one, as kobuki_auto_docking's)."""
        with self.lock:
            self.drive = None
        self._stop()
        text = 'Preempted: New goal received.' if self.server.is_new_goal_available() \
            else 'Cancelled: Cancel requested.'
        self.server.set_preempted(kobuki_msgs.AutoDockingResult(text=text), text)
        rospy.loginfo('fake_dock_drive: %s', text)

    def on_odom(self, msg):
        q = msg.pose.pose.orientation
        self.heading = yaw_from_quaternion(q.x, q.y, q.z, q.w)

    def on_core(self, msg):
        self.core = msg

    def on_ir(self, msg):
        with self.lock:                 # the server is called outside it: actionlib calls in with its own
            drive = self.drive
            if drive is None or self.core is None or self.heading is None:
                return
            v, w = drive.update(bytearray(msg.data), self.core.bumper, self.core.charger, self.heading)
            ended = verdict(drive, rospy.get_time() - self.started, self.time_limit)
            if ended is not None:
                self.drive = None
        if ended is None:
            self.velocity.publish(twist(v, w))
            self.server.publish_feedback(kobuki_msgs.AutoDockingFeedback(state=drive.state, text=''))
            return
        self._stop()
        succeeded, text = ended
        if self.server.is_active():
            (self.server.set_succeeded if succeeded else self.server.set_aborted)(
                kobuki_msgs.AutoDockingResult(text=text), text)
        (rospy.loginfo if succeeded else rospy.logwarn)('fake_dock_drive: %s', text)

    def _stop(self):
        self.velocity.publish(Twist())


def main():
    rospy.init_node('dock_drive')
    FakeDockDrive()
    rospy.spin()


if __name__ == '__main__':
    main()

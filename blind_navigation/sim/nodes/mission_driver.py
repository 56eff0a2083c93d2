#!/usr/bin/env python3
"""Scripted operator: plays a mission (sim/mission.py) as teleop commands.

Publishes the mission's (v, w) on ``cmd_vel`` at its rate from ``start_delay`` s (with
``wait_for_go``, once ``mission_driver/go`` came), then zero and latches ``~done``. A
mission with an ``operator`` watches ``ground_truth`` (sim/operator.py). Zero on
shutdown; it goes on across the clock moving back.
"""
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool, Empty


from blind_navigation.sim.kobuki import MAX_V, MAX_W, clamp
from blind_navigation.sim.mission import load_mission
from blind_navigation.core.geometry import Pose2D
from blind_navigation.ros.clock import LoopClock
from blind_navigation.ros.common import subscribe, twist
from blind_navigation.sim.node_common import MISSION_GO, load_params, odom_state_from_msg
from blind_navigation.ros.odometry import RECEIVE_QUEUE

STOP_MESSAGES = 3


class MissionDriver(object):
    """Params (DEFAULTS): ``mission`` name in config/missions/ or path; ``start_delay`` s;
    ``max_v`` m/s, ``max_w`` rad/s (commands are clamped to these); ``wait_for_go``: start
    only after a message on ``mission_driver/go`` (std_msgs/Empty)."""
    DEFAULTS = {'mission': '', 'start_delay': 1.0, 'max_v': MAX_V, 'max_w': MAX_W, 'wait_for_go': False}

    def __init__(self):
        self.params = p = load_params(self.DEFAULTS)
        if not p.mission:
            raise ValueError('~mission is required (a name in config/missions/ or a path)')
        self.mission = load_mission(p.mission)
        self.cmd = rospy.Publisher('cmd_vel', Twist, queue_size=10)
        self.done = rospy.Publisher('~done', Bool, queue_size=1, latch=True)
        self.done.publish(Bool(False))
        self.operator = self.mission.make_operator()
        self.start = None           # sim s the script started (moved back with the clock)
        self.latest_pose = None
        self.go = threading.Event()
        if p.wait_for_go:
            subscribe(MISSION_GO, Empty, lambda _msg: self.go.set())
        else:
            self.go.set()
        if self.operator is not None:
            subscribe('ground_truth', Odometry, self._on_ground_truth, queue_size=RECEIVE_QUEUE)  # every pose
        rospy.on_shutdown(self.stop)

    def _on_ground_truth(self, msg):
        state = odom_state_from_msg(msg)
        self.latest_pose = Pose2D(state.x, state.y, state.yaw)
        if self.start is not None and self.operator.started:
            self.operator.observe(msg.header.stamp.to_sec() - self.start, self.latest_pose)

    def stop(self):
        self.cmd.publish(Twist())

    def run(self):
        while not rospy.is_shutdown() and rospy.Time.now().is_zero():
            rospy.sleep(0.01)          # wait for /clock
        start = rospy.Time.now() + rospy.Duration(self.params.start_delay)
        rospy.loginfo('mission_driver: %s (%.1f s, %.2f m nominal) starts at sim t %.2f s%s',
                      self.mission.name, self.mission.duration, self.mission.nominal_length(), start.to_sec(),
                      ' at the earliest, after the go on %s' % rospy.resolve_name(MISSION_GO) if self.params.wait_for_go else '')
        rospy.sleep(start - rospy.Time.now())
        if self.params.wait_for_go:
            while not rospy.is_shutdown() and not self.go.wait(0.1):
                pass
            start = rospy.Time.now()
            rospy.loginfo('mission_driver: go at sim t %.2f s', start.to_sec())
        if self.operator is not None:
            while not rospy.is_shutdown() and self.latest_pose is None:
                rospy.logwarn_throttle(5.0, 'mission_driver: waiting for ground_truth (%s)',
                                       rospy.resolve_name('ground_truth'))
                rospy.sleep(0.05)
            start = rospy.Time.now()
            self.operator.start(self.latest_pose)
        self.start = start = start.to_sec()
        rate = LoopClock('mission_driver', then='the script goes on where it was').rate(self.mission.rate)
        while not rospy.is_shutdown():
            t = max(0.0, rospy.get_time() - start)
            command = self.mission.command_at(t) if self.operator is None else self.operator.command(t)
            if command is None:
                break
            v, w = command
            self.cmd.publish(twist(clamp(v, self.params.max_v), clamp(w, self.params.max_w)))
            moved_back = rate.sleep()
            if moved_back:
                start = self.start = start - moved_back
        for _ in range(STOP_MESSAGES):
            self.stop()
            rate.sleep()
        self.done.publish(Bool(True))
        rospy.loginfo('mission_driver: %s done at sim t %.2f s', self.mission.name, rospy.Time.now().to_sec())


def main():
    rospy.init_node('mission_driver')
    try:
        driver = MissionDriver()
    except ValueError as error:
        rospy.logfatal('mission_driver: %s', error)
        raise SystemExit(1)
    try:
        driver.run()
        rospy.spin()
    except rospy.ROSInterruptException:
        pass


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""cmd_vel multiplexer node, a drop-in for yocs_cmd_vel_mux with TurtleBot's configuration.

Subscribes ``~input/<topic>`` for each input (default: safety_controller,
teleop, switch, navi with TurtleBot's priorities and timeouts), forwards the
winner (sim/mux.py rules) to ``~output`` and announces the holder's name, or
``idle``, on the latched ``~active``. The base's own 0.6 s command timeout
stops the robot when the holder goes quiet, as on a real TurtleBot.
"""
import functools
import math

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import String

from blind_navigation.sim.mux import IDLE, TURTLEBOT_INPUTS, CmdVelMux, inputs_from_list
from blind_navigation.ros.clock import every
from blind_navigation.ros.common import shutting_down, subscribe
from blind_navigation.sim.node_common import load_params


class CmdVelMuxNode(object):
    """Params (DEFAULTS): ``subscribers`` list of {name, topic, timeout, priority} ([] = TurtleBot's
    mux.yaml); ``output`` topic; ``check_rate`` Hz (sim time) of the timeout check.
    """
    DEFAULTS = {'subscribers': [], 'output': 'mobile_base/commands/velocity', 'check_rate': 50.0}

    def __init__(self):
        p = load_params(self.DEFAULTS)
        inputs = inputs_from_list(p.subscribers) if p.subscribers else TURTLEBOT_INPUTS
        self.mux = CmdVelMux(inputs)
        self.output = rospy.Publisher(p.output, Twist, queue_size=10)
        self.active = rospy.Publisher('~active', String, queue_size=1, latch=True)
        self.active.publish(String(IDLE))
        self.subscribers = [subscribe('~input/' + entry.topic, Twist,
                                             functools.partial(self.on_command, index), queue_size=10)
                            for index, entry in enumerate(inputs)]
        every(1.0 / p.check_rate, self.on_check, 'cmd_vel_mux timeouts')   # on across a clock jump back

    def on_command(self, index, msg):
        if not all(math.isfinite(x) for x in (msg.linear.x, msg.angular.z)):
            rospy.logerr_throttle(1.0, 'cmd_vel_mux: dropped non-finite command on %s'
                                  % self.mux.inputs[index].topic)
            return
        forward, newly_active = self.mux.offer(index, rospy.Time.now().to_sec())
        try:
            if newly_active:
                self.active.publish(String(newly_active))
            if forward:
                self.output.publish(msg)
        except rospy.ROSException:
            if not shutting_down():   # topics close in a pre-shutdown hook
                raise       # at shutdown the outputs close first: a last command is dropped

    def on_check(self):
        if self.mux.expire(rospy.Time.now().to_sec()) == IDLE:
            self.active.publish(String(IDLE))


def main():
    rospy.init_node('cmd_vel_mux')
    CmdVelMuxNode()
    rospy.spin()


if __name__ == '__main__':
    main()

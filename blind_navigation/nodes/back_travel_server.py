#!/usr/bin/env python3
"""back_travel_server: the paper's action server (sections 3.3.5-3.3.6).

Serves /blind_navigation/back_travel (blind_navigation/BackTravel): each goal is
one path landmark ``(v, w, d, T, psi)``, driven on ``cmd_vel_topic`` by the
core/back_travel.py controller of mode ``control`` (time | distance |
closed_loop). Feedback (distance so far) at ``feedback_rate``; result =
odometry distance and duration. Every goal has a time allowance; a cancel or
preempt publishes zero velocity at once; every command is clamped.

Between goals the last command holds (the next goal follows within
milliseconds); if no new goal starts within ``handover_timeout`` of a success,
zero velocity is published, so the robot stops after the last landmark.

closed_loop: the goals of one return share a core/back_travel.ReturnRoute,
anchored at the odometry position where the state became ``rotating`` (where
recording stopped); without that state, at the start of the first goal.
"""
import threading

import actionlib
import rospy
from std_msgs.msg import String

from blind_navigation.back_travel_ros import (BACK_TRAVEL_ACTION, STATE_TOPIC, LatestOdom,
                                              VelocityOutput)
from blind_navigation.core import state
from blind_navigation.core.back_travel import (BACK_TRAVEL_DEFAULTS, MODES, ReturnRoute,
                                               make_controller)
from blind_navigation.core.landmark import landmark_from_values
from blind_navigation.msg import BackTravelAction, BackTravelFeedback, BackTravelResult
from blind_navigation.ros_common import load_params, start_node


class BackTravelServer(object):
    """Drives one landmark per goal.

    Params (DEFAULTS): ``control`` ('closed_loop'), ``cmd_vel_topic``
    ('/cmd_vel_mux/input/teleop'), ``odom_topic`` ('/odom'), ``control_rate``
    (Hz, 50), ``feedback_rate`` (Hz, 5), ``odom_timeout`` (s, 0.5),
    ``handover_timeout`` (s, 0.1), and core/back_travel.py's
    BACK_TRAVEL_DEFAULTS: ``straight_period`` (s, 2.0: must equal the sampling
    publisher's straight period), ``max_v`` (0.5 m/s), ``max_w`` (1.0 rad/s),
    ``timeout_factor`` (3), ``timeout_margin`` (2 s), ``lookahead`` (0.1 m),
    ``min_v`` (0.03 m/s), ``min_d`` (0.002 m).
    """

    DEFAULTS = dict(BACK_TRAVEL_DEFAULTS, control='closed_loop',
                    cmd_vel_topic='/cmd_vel_mux/input/teleop', odom_topic='/odom',
                    control_rate=50.0, feedback_rate=5.0, odom_timeout=0.5, handover_timeout=0.1)

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        if p.control not in MODES:
            raise ValueError('~control must be one of %s, got %r' % (', '.join(MODES), p.control))
        for name in ('control_rate', 'feedback_rate', 'odom_timeout', 'handover_timeout',
                     'straight_period'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        self.output = VelocityOutput(p.cmd_vel_topic, p.max_v, p.max_w)
        self.odom = LatestOdom(p.odom_topic)
        self._lock = threading.Lock()
        self._active = False
        self._handover = None
        self.route = None
        rospy.Subscriber(STATE_TOPIC, String, self._on_state, queue_size=5)
        self.server = actionlib.SimpleActionServer(BACK_TRAVEL_ACTION, BackTravelAction,
                                                   execute_cb=self.execute, auto_start=False)
        self.server.register_preempt_callback(self._on_preempt)
        self.server.start()
        rospy.loginfo('%s: serving %s in %s mode on %s', rospy.get_name(), BACK_TRAVEL_ACTION,
                      p.control, p.cmd_vel_topic)

    def _on_state(self, msg):
        if msg.data == state.ROTATING:
            odom = self.odom.fresh(self.params.odom_timeout)
            with self._lock:
                self.route = ReturnRoute((odom.x, odom.y) if odom else None,
                                         self.params.straight_period)
            rospy.loginfo('%s: new return route anchored at %s', rospy.get_name(),
                          '(%.3f, %.3f)' % (odom.x, odom.y) if odom else 'the first goal')

    def _on_preempt(self):
        self.output.stop()  # at once, not at the next control cycle

    def _on_handover_timeout(self, _event):
        with self._lock:
            if not self._active:
                self.output.stop()

    def execute(self, goal):
        with self._lock:
            self._active = True
            if self._handover is not None:
                self._handover.shutdown()
                self._handover = None
            if self.route is None:
                self.route = ReturnRoute(straight_period=self.params.straight_period)
        try:
            outcome = self._run(goal)
        except Exception as error:  # never leave the robot moving or the goal hanging
            rospy.logerr('%s: goal failed: %s', rospy.get_name(), error)
            self.output.stop()
            outcome = ('aborted', BackTravelResult(), 'internal error: %s' % error)
        kind, result, text = outcome
        with self._lock:
            self._active = False
            if kind == 'succeeded':
                self._handover = rospy.Timer(rospy.Duration(self.params.handover_timeout),
                                             self._on_handover_timeout, oneshot=True)
        getattr(self.server, 'set_' + kind)(result, text)

    def _run(self, goal):
        """Drive one goal; returns (succeeded|preempted|aborted, result, text)."""
        p = self.params
        values = [goal.v, goal.w, goal.d, goal.T, goal.psi]
        try:
            landmark = landmark_from_values(values)
        except ValueError as error:
            self.output.stop()
            return 'aborted', BackTravelResult(), 'bad goal %r: %s' % (values, error)
        odom = self.odom.fresh(p.odom_timeout)
        if odom is None:
            self.output.stop()
            return 'aborted', BackTravelResult(), self.odom.describe_missing(p.odom_timeout)
        controller = make_controller(p.control, landmark, p, self.route)
        controller.start(odom)
        started = odom.stamp
        result = lambda: BackTravelResult(distance=controller.travelled,
                                          duration=rospy.Time.now().to_sec() - started)
        rate = rospy.Rate(p.control_rate)
        next_feedback = started
        while True:
            if self.server.is_preempt_requested() or rospy.is_shutdown():
                self.output.stop()
                return 'preempted', result(), 'preempted after %.3f m' % controller.travelled
            odom = self.odom.fresh(p.odom_timeout)
            if odom is None:
                self.output.stop()
                return 'aborted', result(), self.odom.describe_missing(p.odom_timeout)
            v, w = controller.step(odom)
            if controller.failed:
                self.output.stop()
                return 'aborted', result(), ('time allowance %.1f s exceeded after %.3f m of %.3f m'
                                             % (controller.allowance, controller.travelled, landmark.d))
            if controller.done:
                return 'succeeded', result(), ''
            self.output.publish(v, w)
            if odom.stamp >= next_feedback:
                self.server.publish_feedback(BackTravelFeedback(distance=controller.travelled))
                next_feedback = odom.stamp + 1.0 / p.feedback_rate
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                self.output.stop()
                return 'preempted', result(), 'node shutting down'


def main():
    start_node('back_travel_server', BackTravelServer)
    rospy.spin()


if __name__ == '__main__':
    main()

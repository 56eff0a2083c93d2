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
set by back_travel_client through /blind_navigation/set_return_route
(blind_navigation/SetReturnRoute: the anchor where recording stopped and the
landmarks already completed, so a restarted layer resumes on the same route);
without it, anchored at the start of the first goal.

Safety (core/safety.py, docs/safety.md): each goal is clamped to ``max_v`` /
``max_w`` and to what was recorded (goal_limits); odometry older than
``odom_timeout`` aborts the goal with zero velocity; a Kobuki bumper, cliff or
wheel-drop event halts the output at once (zero velocity, from the event
callback) and aborts the goal naming the sensor; while a sensor is still
active no goal starts. Cancel, error and shutdown publish zero velocity.
"""
import threading
import types

import actionlib
import rospy

from blind_navigation import names
from blind_navigation.ros.back_travel_common import LatestOdom, SafetyMonitor, VelocityOutput
from blind_navigation.core.back_travel import (BACK_TRAVEL_DEFAULTS, MODES, ReturnRoute,
                                               make_controller)
from blind_navigation.core.landmark import landmark_from_values
from blind_navigation.core.safety import SAFETY_DEFAULTS, goal_limits, landmarks_from_flat
from blind_navigation.msg import BackTravelAction, BackTravelFeedback, BackTravelResult
from blind_navigation.ros.common import load_params
from blind_navigation.srv import SetReturnRoute, SetReturnRouteResponse


class BackTravelServer(object):
    """Drives one landmark per goal.

    Params (DEFAULTS): ``control`` ('closed_loop'), ``cmd_vel_topic``
    ('/cmd_vel_mux/input/teleop'), ``odom_topic`` ('/odom'), ``control_rate``
    (Hz, 50), ``feedback_rate`` (Hz, 5), ``odom_timeout`` (s, 0.4: older
    odometry stops the robot), ``handover_timeout`` (s, 0.1),
    ``correction_w`` (rad/s, 0.3: a goal may turn this much beyond its
    recorded |w|), ``bumper_topic`` / ``cliff_topic`` / ``wheel_drop_topic``
    (Kobuki's /mobile_base/events/*), and core/back_travel.py's
    BACK_TRAVEL_DEFAULTS: ``straight_period`` (s, 2.0: must equal the sampling
    publisher's straight period), ``max_v`` (0.5 m/s), ``max_w`` (1.0 rad/s),
    ``timeout_factor`` (3), ``timeout_margin`` (2 s), ``lookahead`` (0.1 m),
    ``min_v`` (0.03 m/s), ``min_d`` (0.002 m).
    """

    DEFAULTS = dict(BACK_TRAVEL_DEFAULTS, control='closed_loop',
                    cmd_vel_topic='/cmd_vel_mux/input/teleop', odom_topic='/odom',
                    control_rate=50.0, feedback_rate=5.0, odom_timeout=0.4, handover_timeout=0.1,
                    correction_w=SAFETY_DEFAULTS['correction_w'],
                    **{kind + '_topic': topic for kind, topic in names.SAFETY_EVENTS.items()})

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        if p.control not in MODES:
            raise ValueError('~control must be one of %s, got %r' % (', '.join(MODES), p.control))
        for name in ('control_rate', 'feedback_rate', 'odom_timeout', 'handover_timeout',
                     'straight_period'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        if not p.correction_w >= 0:
            raise ValueError('~correction_w must be >= 0, got %r' % (p.correction_w,))
        self.output = VelocityOutput(p.cmd_vel_topic, p.max_v, p.max_w)
        self.odom = LatestOdom(p.odom_topic)
        self._lock = threading.Lock()
        self._active = False
        self._handover = None
        self._tripped = None        # safety reason that stopped the current goal
        self.route = None
        self.safety = SafetyMonitor({kind: getattr(p, kind + '_topic') for kind in names.SAFETY_EVENTS},
                                    self._on_trip)
        rospy.Service(names.SET_RETURN_ROUTE, SetReturnRoute, self._on_set_route)
        self.server = actionlib.SimpleActionServer(names.BACK_TRAVEL, BackTravelAction,
                                                   execute_cb=self.execute, auto_start=False)
        self.server.register_preempt_callback(self._on_preempt)
        self.server.start()
        rospy.loginfo('%s: serving %s in %s mode on %s', rospy.get_name(), names.BACK_TRAVEL,
                      p.control, p.cmd_vel_topic)

    def _on_set_route(self, request):
        """A new return route: anchor + the landmarks already completed."""
        try:
            completed = landmarks_from_flat(request.completed)
        except ValueError as error:
            return SetReturnRouteResponse(ok=False, message=str(error))
        route = ReturnRoute((request.anchor_x, request.anchor_y), self.params.straight_period)
        for landmark in completed:
            route.add(landmark)
            route.locate(*route.points[-1])   # progress tracking follows the rebuilt route
        with self._lock:
            self.route = route
        rospy.loginfo('%s: return route anchored at (%.3f, %.3f) in %s, %d landmarks completed',
                      rospy.get_name(), request.anchor_x, request.anchor_y,
                      request.header.frame_id or '?', len(completed))
        return SetReturnRouteResponse(ok=True, message='')

    def _on_trip(self, reason):
        with self._lock:
            if self._active:
                self._tripped = reason
                self.output.halt('safety: ' + reason)  # at once, from the event callback

    def _on_preempt(self):
        self.output.halt('cancel')  # at once, not at the next control cycle

    def _on_handover_timeout(self, _event):
        with self._lock:
            if not self._active:
                self.output.stop()

    def execute(self, goal):
        with self._lock:
            self._active = True
            self._tripped = None
            if self._handover is not None:
                self._handover.shutdown()
                self._handover = None
            if self.route is None:
                self.route = ReturnRoute(straight_period=self.params.straight_period)
        try:
            outcome = self._run(goal)
        except Exception as error:  # never leave the robot moving or the goal hanging
            rospy.logerr('%s: goal failed: %s', rospy.get_name(), error)
            self.output.halt('error')
            outcome = ('aborted', BackTravelResult(), 'internal error: %s' % error)
        kind, result, text = outcome
        if kind == 'aborted':
            rospy.logerr('%s: goal aborted: %s', rospy.get_name(), text)
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
        if self.safety.active:
            self.output.halt('safety')
            return 'aborted', BackTravelResult(), 'safety stop: %s' % ', '.join(self.safety.active)
        odom = self.odom.fresh(p.odom_timeout)
        if odom is None:
            self.output.halt('odometry')
            return 'aborted', BackTravelResult(), self.odom.describe_missing(p.odom_timeout)
        limits = goal_limits(landmark, p.max_v, p.max_w, p.correction_w)
        self.output.limit(limits)
        self.output.release()
        goal_params = types.SimpleNamespace(**dict(
            {name: getattr(p, name) for name in self.DEFAULTS}, max_v=limits.max_v))
        controller = make_controller(p.control, landmark, goal_params, self.route)
        controller.start(odom)
        started = odom.stamp
        result = lambda: BackTravelResult(distance=controller.travelled,
                                          duration=rospy.Time.now().to_sec() - started)
        rate = rospy.Rate(p.control_rate)
        next_feedback = started
        while True:
            if self._tripped:
                self.output.halt('safety')
                return 'aborted', result(), 'safety stop: %s after %.3f m' % (self._tripped,
                                                                              controller.travelled)
            if self.server.is_preempt_requested() or rospy.is_shutdown():
                self.output.halt('cancel')
                return 'preempted', result(), 'preempted after %.3f m' % controller.travelled
            odom = self.odom.fresh(p.odom_timeout)
            if odom is None:
                self.output.halt('odometry')
                return 'aborted', result(), self.odom.describe_missing(p.odom_timeout)
            v, w = controller.step(odom)
            if controller.failed:
                self.output.halt('time allowance')
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
                self.output.halt('node shutdown')
                return 'preempted', result(), 'node shutting down'

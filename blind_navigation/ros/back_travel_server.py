"""The back-travel server: the paper's action server (sections 3.3.5-3.3.6).

Serves ``blind_navigation/back_travel`` (blind_navigation/BackTravel): each
goal is one path landmark ``(v, w, d, T, psi)``, driven on ``cmd_vel`` by the
core/back_travel.py controller of mode ``control`` (time | distance |
closed_loop). Feedback (distance so far) at ``feedback_rate``; result =
odometry distance and duration.

It serves its own mission only: a goal is accepted while the mission is
``returning``, from the mission's owner (back_travel_client, the node that
owns the mission state), one at a time; any other goal is rejected with the
reason (a second client neither preempts nor drives). When the mission leaves
``returning`` the active goal is aborted and the output halted at once
(ros/motion.MotionOutput moves only in ``returning``).

closed_loop: the goals of one return share a core/back_travel.ReturnRoute, set
by back_travel_client through ``blind_navigation/set_return_route``
(blind_navigation/SetReturnRoute: the anchor where recording stopped and the
landmarks already completed, so a restarted layer resumes on the same route).
The anchor must be finite and within ``route_max_offset`` of the robot, where
the completed landmarks leave it; anything else is refused.

Between goals the last command holds (the next goal follows within
milliseconds); if no new goal starts within ``handover_timeout`` of a success,
zero velocity is published, so the robot stops after the last landmark.

Safety (core/safety.py, docs/safety.md): each goal is clamped to ``max_v`` /
``max_w`` and to what was recorded (goal_limits); odometry older than
``odom_timeout`` commands zero at once and holds the goal, which continues if
odometry comes back within ``odom_grace`` s and is aborted otherwise; a Kobuki
bumper, cliff or wheel-drop event halts the output at once and aborts the goal
naming the sensor; while a sensor is still active no goal starts. Cancel,
error and shutdown publish zero velocity.

Params (``layer.params``): core/back_travel's BACK_TRAVEL_DEFAULTS (but
``straight_period``: from the shared ``straight_rate``), ``control`` (set by
the launch files),
``control_rate``, ``feedback_rate`` (Hz), ``odom_timeout``, ``odom_grace``,
``handover_timeout`` (s), ``correction_w`` (rad/s a goal may turn beyond its
recorded |w|), ``route_max_offset`` (m).
"""
import math
import threading
import types

import actionlib
import rospy

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.back_travel import (BACK_TRAVEL_DEFAULTS, MODES, ReturnRoute,
                                               make_controller)
from blind_navigation.core.geometry import distance
from blind_navigation.core.landmark import landmark_from_values
from blind_navigation.core.safety import SAFETY_DEFAULTS, goal_limits, landmarks_from_flat
from blind_navigation.core.segment import SAMPLING_DEFAULTS, period_of
from blind_navigation.msg import BackTravelAction, BackTravelFeedback, BackTravelResult
from blind_navigation.ros.common import REQUIRED
from blind_navigation.ros.motion import MotionOutput
from blind_navigation.srv import SetReturnRoute, SetReturnRouteResponse


class BackTravelServer(object):
    """Drives one landmark per goal (module docstring)."""

    ROLE = mission_state.BACK_TRAVEL_ROLE
    DEFAULTS = dict({k: v for k, v in BACK_TRAVEL_DEFAULTS.items() if k != 'straight_period'},
                    control=REQUIRED, straight_rate=SAMPLING_DEFAULTS['straight_rate'],
                    control_rate=50.0, feedback_rate=5.0, odom_timeout=0.4, odom_grace=3.0,
                    handover_timeout=0.1, correction_w=SAFETY_DEFAULTS['correction_w'],
                    route_max_offset=0.5)

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.DEFAULTS, shared=('straight_rate',))
        self.log = layer.logger(self.ROLE)
        if p.control not in MODES:
            raise ValueError('~control must be one of %s, got %r' % (', '.join(MODES), p.control))
        for name in ('control_rate', 'feedback_rate', 'odom_timeout', 'handover_timeout',
                     'route_max_offset'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        if not p.correction_w >= 0 or not p.odom_grace >= 0:
            raise ValueError('~correction_w and ~odom_grace must be >= 0 (%r, %r)'
                             % (p.correction_w, p.odom_grace))
        self.straight_period = period_of(p.straight_rate, '~straight_rate')
        self.layer = layer
        self.odometry = layer.odometry
        self.output = MotionOutput(self.ROLE, p.max_v, p.max_w, layer.mission, layer.safety)
        layer.heading_correction()       # drive on the corrected odometry once it exists
        self._lock = threading.Lock()
        self._active = None              # the goal handle being driven
        self._pending = None             # the accepted goal handle waiting for the worker
        self._wake = threading.Event()
        self._handover = None
        self._tripped = None             # safety reason that stopped the current goal
        self.route = None
        layer.safety.on_trip(self._on_trip)
        layer.mission.on_change(self._on_state)
        rospy.Service(names.SET_RETURN_ROUTE, SetReturnRoute, self._on_set_route)
        self.server = actionlib.ActionServer(names.BACK_TRAVEL, BackTravelAction, self._on_goal,
                                             self._on_cancel, auto_start=False)
        self.server.start()
        threading.Thread(target=self._work, name='back_travel_goals', daemon=True).start()
        self.log.info('serving %s in %s mode on %s', rospy.resolve_name(names.BACK_TRAVEL),
                      p.control, rospy.resolve_name(names.CMD_VEL))

    # --- who may send what -------------------------------------------------------------------
    def _on_set_route(self, request):
        """A new return route: anchor + the landmarks already completed."""
        problem = self._route_problem(request)
        if problem:
            self.log.error('return route refused: %s', problem)
            return SetReturnRouteResponse(ok=False, message=problem)
        completed = landmarks_from_flat(request.completed)
        route = ReturnRoute((request.anchor_x, request.anchor_y), self.straight_period)
        for landmark in completed:
            route.add(landmark)
            route.locate(*route.points[-1])   # progress tracking follows the rebuilt route
        with self._lock:
            self.route = route
        self.odometry.acquire(self.ROLE)
        self.log.info('return route anchored at (%.3f, %.3f) in %s, %d landmarks completed',
                      request.anchor_x, request.anchor_y, request.header.frame_id or '?',
                      len(completed))
        return SetReturnRouteResponse(ok=True, message='')

    def _route_problem(self, request):
        """Why a SetReturnRoute request is refused, or None."""
        state = self.layer.mission.state
        if state != mission_state.RETURNING:
            return 'the mission is %s, not returning' % state
        sender = request._connection_header.get('callerid', '?')
        if sender != self.layer.mission_owner:
            return 'only %s sets the return route, not %s' % (self.layer.mission_owner, sender)
        if not (math.isfinite(request.anchor_x) and math.isfinite(request.anchor_y)):
            return 'anchor (%r, %r) is not finite' % (request.anchor_x, request.anchor_y)
        try:
            completed = landmarks_from_flat(request.completed)
        except ValueError as error:
            return str(error)
        odom = self.odometry.fresh(self.params.odom_grace) or self._wait_for_odometry()
        if odom is None:
            return 'no odometry to check where the robot is'
        route = ReturnRoute((request.anchor_x, request.anchor_y), self.straight_period)
        for landmark in completed:
            route.add(landmark)
        offset = distance(odom.x, odom.y, *route.points[-1])
        if offset > self.params.route_max_offset:
            return ('the robot is %.2f m from where the route continues (%.2f, %.2f) after %d '
                    'landmarks (route_max_offset %.2f m)' % (offset, route.points[-1][0],
                                                            route.points[-1][1], len(completed),
                                                            self.params.route_max_offset))
        return None

    def _wait_for_odometry(self):
        self.odometry.acquire(self.ROLE)
        deadline = rospy.get_time() + self.params.odom_grace
        odom = None
        while odom is None and rospy.get_time() < deadline and not rospy.is_shutdown():
            rospy.sleep(0.02)
            odom = self.odometry.fresh(self.params.odom_timeout)
        return odom

    def _on_goal(self, handle):
        problem = self._goal_problem(handle)
        if problem:
            self.log.error('goal %s rejected: %s', handle.get_goal_id().id, problem)
            handle.set_rejected(BackTravelResult(), problem)
            return
        with self._lock:
            self._pending = handle
        handle.set_accepted()
        self._wake.set()

    def _goal_problem(self, handle):
        state = self.layer.mission.state
        if state != mission_state.RETURNING:
            return 'the mission is %s, not returning' % state
        sender = handle.goal._connection_header.get('callerid', '?') if handle.goal else '?'
        if sender != self.layer.mission_owner:
            return 'only %s sends back-travel goals, not %s' % (self.layer.mission_owner, sender)
        with self._lock:
            if self._active is not None or self._pending is not None:
                return 'a goal is being driven (one at a time)'
        if self.params.control == 'closed_loop' and self.route is None:
            return 'no return route set (%s)' % rospy.resolve_name(names.SET_RETURN_ROUTE)
        return None

    def _on_cancel(self, handle):
        with self._lock:
            ours = handle in (self._active, self._pending)
        if ours:
            self.output.halt('cancel')  # at once, not at the next control cycle

    def _on_trip(self, reason):
        with self._lock:
            if self._active is not None:
                self._tripped = reason

    def _on_state(self, _old, new):
        if new in mission_state.TERMINAL:
            self.odometry.release(self.ROLE)

    def _on_handover_timeout(self, _event):
        with self._lock:
            if self._active is None:
                self.output.stop()

    # --- driving -----------------------------------------------------------------------------
    def _work(self):
        while not rospy.is_shutdown():
            if not self._wake.wait(0.2):
                continue
            self._wake.clear()
            with self._lock:
                handle, self._pending = self._pending, None
                if handle is None:
                    continue
                self._active = handle
                self._tripped = None
                if self._handover is not None:
                    self._handover.shutdown()
                    self._handover = None
            self.execute(handle)

    def execute(self, handle):
        try:
            kind, result, text = self._run(handle)
        except Exception as error:  # never leave the robot moving or the goal hanging
            self.log.error('goal failed: %s', error)
            self.output.halt('error')
            kind, result, text = 'aborted', BackTravelResult(), 'internal error: %s' % error
        if kind == 'aborted':
            self.log.error('goal aborted: %s', text)
        with self._lock:
            self._active = None
            if kind == 'succeeded':
                self._handover = rospy.Timer(rospy.Duration(self.params.handover_timeout),
                                             self._on_handover_timeout, oneshot=True)
        getattr(handle, {'succeeded': 'set_succeeded', 'aborted': 'set_aborted',
                         'canceled': 'set_canceled'}[kind])(result, text)

    def _cancelled(self, handle):
        return handle.get_goal_status().status in (actionlib.GoalStatus.PREEMPTING,
                                                   actionlib.GoalStatus.RECALLING)

    def _run(self, handle):
        """Drive one goal; returns (succeeded|canceled|aborted, result, text)."""
        p = self.params
        goal = handle.get_goal()
        values = [goal.v, goal.w, goal.d, goal.T, goal.psi]
        try:
            landmark = landmark_from_values(values)
        except ValueError as error:
            self.output.stop()
            return 'aborted', BackTravelResult(), 'bad goal %r: %s' % (values, error)
        if self.layer.safety.active:
            self.output.halt('safety')
            return 'aborted', BackTravelResult(), 'safety stop: %s' % ', '.join(self.layer.safety.active)
        odom = self.odometry.fresh(p.odom_timeout) or self._wait_for_odometry()
        if odom is None:
            self.output.halt('odometry')
            return 'aborted', BackTravelResult(), self.odometry.describe_missing(p.odom_timeout)
        limits = goal_limits(landmark, p.max_v, p.max_w, p.correction_w)
        self.output.limit(limits)
        self.output.release()
        goal_params = types.SimpleNamespace(**dict(
            {name: getattr(p, name) for name in self.DEFAULTS if hasattr(p, name)},
            max_v=limits.max_v, straight_period=self.straight_period))
        controller = make_controller(p.control, landmark, goal_params, self.route)
        controller.start(odom)
        started = odom.stamp
        result = lambda: BackTravelResult(distance=controller.travelled,
                                          duration=rospy.get_time() - started)
        rate = rospy.Rate(p.control_rate)
        next_feedback = started
        held_since = None
        while True:
            if self._tripped:
                self.output.halt('safety')
                return 'aborted', result(), 'safety stop: %s after %.3f m' % (self._tripped,
                                                                              controller.travelled)
            if self._cancelled(handle) or rospy.is_shutdown():
                self.output.halt('cancel')
                return 'canceled', result(), 'canceled after %.3f m' % controller.travelled
            if self.layer.mission.state != mission_state.RETURNING:
                return 'aborted', result(), 'the mission is %s' % self.layer.mission.state
            odom = self.odometry.fresh(p.odom_timeout)
            now = rospy.get_time()
            if odom is None:
                if held_since is None:
                    held_since = now
                    self.output.stop()
                    self.log.warn('goal held: %s', self.odometry.describe_missing(p.odom_timeout))
                elif now - held_since > p.odom_grace:
                    self.output.halt('odometry')
                    return 'aborted', result(), '%s for %.1f s (odom_grace %.1f s)' % (
                        self.odometry.describe_missing(p.odom_timeout), now - held_since, p.odom_grace)
                self._sleep(rate)
                continue
            if held_since is not None:
                self.log.warn('goal resumed after a %.2f s hold without odometry', now - held_since)
                held_since = None
            v, w = controller.step(odom)
            if controller.failed:
                self.output.halt('time allowance')
                return 'aborted', result(), ('time allowance %.1f s exceeded after %.3f m of %.3f m'
                                             % (controller.allowance, controller.travelled, landmark.d))
            if controller.done:
                return 'succeeded', result(), ''
            self.output.publish(v, w)
            if odom.stamp >= next_feedback:
                handle.publish_feedback(BackTravelFeedback(distance=controller.travelled))
                next_feedback = odom.stamp + 1.0 / p.feedback_rate
            self._sleep(rate)

    @staticmethod
    def _sleep(rate):
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            pass

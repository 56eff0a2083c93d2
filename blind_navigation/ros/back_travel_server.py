"""The back-travel server: the paper's action server (sections 3.3.5-3.3.6).

Serves ``blind_navigation/back_travel`` (blind_navigation/BackTravel): each
goal is one path landmark ``(v, w, d, T, psi)``, driven on ``cmd_vel`` in the
mode ``control`` (core/goal.py): ``time`` and ``distance`` (the landmark's own
controller, core/back_travel.py) or ``closed_loop`` (the goals of a return
share one core/back_travel.RouteFollower over the route the mission's owner
set with ``blind_navigation/set_return_route``; a goal ends when its section is
done). Feedback: the distance so far; result: odometry distance and duration.

It serves its own mission only: a goal is accepted while the mission is
``returning``, from the mission's owner, one at a time, and only if it is the
next landmark of the route. Between goals the last command holds for at most
``handover_timeout`` (core/goal.CommandHold). Every command is clamped and
state-gated (ros/motion.MotionOutput); stale or refused odometry holds the goal
(core/allowance.OdomGrace), a Kobuki event aborts it; cancel, error and
shutdown publish zero velocity. Details and reasons: docs/back_travel.md,
docs/safety.md.
"""
import threading
import types

import actionlib
import rospy

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.allowance import ABORT, ALLOWANCE_DEFAULTS, HOLD, OdomGrace
from blind_navigation.core.back_travel import BACK_TRAVEL_DEFAULTS, MODES, RouteFollower
from blind_navigation.core.geometry import distance
from blind_navigation.core.goal import CommandHold, make_goal
from blind_navigation.core.landmark import landmark_from_values
from blind_navigation.core.safety import goal_limits, landmarks_from_flat
from blind_navigation.core.segment import SAMPLING_DEFAULTS, period_of
from blind_navigation.msg import BackTravelAction, BackTravelFeedback, BackTravelResult
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import REQUIRED, shutting_down
from blind_navigation.ros.faults import describe
from blind_navigation.ros.motion import MotionOutput
from blind_navigation.ros.route_wire import route_of
from blind_navigation.srv import SetReturnRoute, SetReturnRouteResponse


class BackTravelServer(object):
    """Drives one landmark per goal (module docstring)."""

    ROLE = mission_state.BACK_TRAVEL_ROLE
    DEFAULTS = dict({k: v for k, v in BACK_TRAVEL_DEFAULTS.items() if k != 'straight_period'},
                    **ALLOWANCE_DEFAULTS,
                    control=REQUIRED,           # time, distance or closed_loop (core/goal.py)
                    straight_rate=SAMPLING_DEFAULTS['straight_rate'],  # Hz; a landmark with T >=
                                                # 1 / straight_rate is a straight segment
                    control_rate=50.0,          # Hz of the control loop
                    feedback_rate=5.0,          # Hz of the action's feedback
                    handover_timeout=0.1,       # s the last command holds after a goal published
                                                # it, between goals; then zero velocity
                    route_max_offset=0.5,       # m from where the route continues: a route is refused
                    status_frequency=1.0)       # Hz of the action server's periodic status

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.DEFAULTS, shared=('straight_rate',))
        self.log = layer.logger(self.ROLE)
        if p.control not in MODES:
            raise ValueError('~control must be one of %s, got %r' % (', '.join(MODES), p.control))
        for name in ('control_rate', 'feedback_rate', 'handover_timeout', 'route_max_offset',
                     'status_frequency'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        OdomGrace(p)                     # validates the odometry params now
        self.straight_period = period_of(p.straight_rate, '~straight_rate')
        self.goal_params = types.SimpleNamespace(**dict(
            {name: getattr(p, name) for name in self.DEFAULTS}, straight_period=self.straight_period))
        self.layer = layer
        self.odometry = layer.odometry
        self.output = MotionOutput(self.ROLE, p.max_v, p.max_w, layer.mission, layer.safety)
        layer.heading_correction()       # drive on the corrected odometry once it exists
        self._lock = threading.Lock()
        self._active = None              # the goal handle being driven
        self._pending = None             # the accepted goal handle waiting for the worker
        self._wake = threading.Event()
        self.hold = CommandHold(p.handover_timeout)   # the output between goals
        self._tripped = None             # safety reason that stopped the current goal
        self.route = None                # core Route of the return
        self.landmarks = []              # its goals' landmarks, return order
        self.next_goal = 0               # index of the goal the route expects next
        self.follower = None             # closed_loop: the RouteFollower of the return
        guard = self.guard = layer.guard(self.ROLE)
        layer.safety.on_trip(guard(self._on_trip))
        layer.mission.on_change(guard(self._on_state))
        rospy.Service(names.SET_RETURN_ROUTE, SetReturnRoute, guard(self._on_set_route))
        self.server = actionlib.ActionServer(names.BACK_TRAVEL, BackTravelAction,
                                             guard(self._on_goal), guard(self._on_cancel),
                                             auto_start=False)
        # actionlib reads it in start(), searching from the node's private namespace first
        rospy.set_param('~actionlib_status_frequency', p.status_frequency)
        self.server.start()
        rospy.on_shutdown(self._wake.set)
        threading.Thread(target=guard(self._work), name='back_travel_goals', daemon=True).start()
        self.last_abort = ''
        layer.diagnostics.add('back travel', self._diagnose)
        self.log.info('serving %s in %s mode on %s', rospy.resolve_name(names.BACK_TRAVEL),
                      p.control, rospy.resolve_name(names.CMD_VEL))

    # --- who may send what -------------------------------------------------------------------
    def _on_set_route(self, request):
        """The return's route, its goals' landmarks and how many are done."""
        try:
            route, landmarks = self._read_route(request)
        except ValueError as error:
            self.log.error('return route refused: %s', error)
            return SetReturnRouteResponse(ok=False, message=str(error))
        with self._lock:
            if self._active is not None or self._pending is not None:
                return SetReturnRouteResponse(ok=False, message='a goal is being driven')
            self.route, self.landmarks, self.next_goal = route, landmarks, request.completed
            self.follower = RouteFollower(route, self.goal_params) \
                if self.params.control == 'closed_loop' else None
        self.log.info('return route of %d landmarks (%.2f m) in %s, %d completed',
                      len(landmarks), route.length, request.header.frame_id or '?', request.completed)
        return SetReturnRouteResponse(ok=True, message='')

    def _read_route(self, request):
        """(Route, landmarks) of a SetReturnRoute request; ValueError naming what is wrong."""
        state = self.layer.mission.state
        if state != mission_state.RETURNING:
            raise ValueError('the mission is %s, not returning' % state)
        sender = request._connection_header.get('callerid', '?')
        if sender != self.layer.mission_owner:
            raise ValueError('only %s sets the return route, not %s' % (self.layer.mission_owner, sender))
        route = route_of(request)
        landmarks = landmarks_from_flat(request.landmarks)
        if len(landmarks) != len(route.sections):
            raise ValueError('%d landmarks for a route of %d sections'
                             % (len(landmarks), len(route.sections)))
        if request.completed > len(landmarks):
            raise ValueError('completed %d of only %d landmarks' % (request.completed, len(landmarks)))
        odom = self.odometry.fresh(self.params.odom_timeout) or self._wait_for_odometry()
        if odom is None:
            raise ValueError('no odometry to check where the robot is')
        vertex = route.sections[request.completed - 1].end_vertex if request.completed else 0
        x, y = route.x[int(vertex)], route.y[int(vertex)]
        offset = distance(odom.x, odom.y, x, y)
        if offset > self.params.route_max_offset:
            raise ValueError('the robot is %.2f m from where the route continues (%.2f, %.2f) after '
                             '%d landmarks (route_max_offset %.2f m)'
                             % (offset, x, y, request.completed, self.params.route_max_offset))
        return route, landmarks

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
        """Why a goal is rejected, or None (module docstring)."""
        state = self.layer.mission.state
        if state != mission_state.RETURNING:
            return 'the mission is %s, not returning' % state
        sender = handle.goal._connection_header.get('callerid', '?') if handle.goal else '?'
        if sender != self.layer.mission_owner:
            return 'only %s sends back-travel goals, not %s' % (self.layer.mission_owner, sender)
        goal = handle.get_goal()
        values = [goal.v, goal.w, goal.d, goal.T, goal.psi]
        try:
            landmark = landmark_from_values(values)
        except ValueError as error:
            return 'bad goal %r: %s' % (values, error)
        with self._lock:
            if self._active is not None or self._pending is not None:
                return 'a goal is being driven (one at a time)'
            if self.route is None:
                return 'no return route set (%s)' % rospy.resolve_name(names.SET_RETURN_ROUTE)
            if self.next_goal >= len(self.landmarks):
                return 'the route has no goal left (%d done)' % self.next_goal
            expected = self.landmarks[self.next_goal]
        if tuple(landmark) != tuple(expected):
            return 'not the next landmark of the route (goal %d expects %r)' % (
                self.next_goal + 1, list(expected))
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
        if new == mission_state.RETURNING:
            self.odometry.acquire(self.ROLE)
        elif new in mission_state.TERMINAL:
            self.odometry.release(self.ROLE)

    def _diagnose(self, stat):
        stat.add('control', self.params.control)
        stat.add('goals done', '%d of %d' % (self.next_goal, len(self.landmarks)))
        if self.layer.mission.state == mission_state.RETURNING:
            diagnostics.age_status(stat, 'odometry', self.odometry.age(), self.params.odom_timeout,
                                   diagnostics.ERROR,
                                   listening=self.odometry.listening())
        elif self.last_abort:
            stat.summary(diagnostics.ERROR, 'last goal aborted: %s' % self.last_abort)
        else:
            stat.summary(diagnostics.OK, 'ready' if self.route is None else 'route set')

    def _schedule_handover(self):
        """Zero velocity once the last command no longer holds (core/goal.CommandHold)."""
        remaining = self.hold.remaining(rospy.get_time())
        if remaining > 0:
            rospy.Timer(rospy.Duration(remaining), self.guard(self._on_handover_timeout),
                        oneshot=True)
        else:
            self._on_handover_timeout(None)

    def _on_handover_timeout(self, _event):
        with self._lock:
            if self.hold.expired(rospy.get_time()):
                self.output.stop()

    # --- driving -----------------------------------------------------------------------------
    def _work(self):
        while True:
            self._wake.wait()           # a goal, or shutdown
            if shutting_down():
                return
            self._wake.clear()
            with self._lock:
                handle, self._pending = self._pending, None
                if handle is None:
                    continue
                self._active = handle
                self._tripped = None
            self.execute(handle)

    def execute(self, handle):
        try:
            kind, result, text = self._run(handle)
        except Exception as error:  # never leave the robot moving or the goal hanging
            self.layer.faults.fail(self.ROLE, error, 'BackTravelServer._run')
            kind, result, text = 'aborted', BackTravelResult(), describe(self.ROLE, error)
        if kind == 'aborted':
            self.log.error('goal aborted: %s', text)
            self.last_abort = text
        with self._lock:
            self._active = None
            if kind == 'succeeded':
                self.next_goal += 1
        if kind == 'succeeded':
            self._schedule_handover()
        getattr(handle, {'succeeded': 'set_succeeded', 'aborted': 'set_aborted',
                         'canceled': 'set_canceled'}[kind])(result, text)

    @staticmethod
    def _cancelled(handle):
        return handle.get_goal_status().status in (actionlib.GoalStatus.PREEMPTING,
                                                   actionlib.GoalStatus.RECALLING)

    def _run(self, handle):
        """Drive one goal; returns (succeeded|canceled|aborted, result, text)."""
        p = self.params
        goal_message = handle.get_goal()
        landmark = landmark_from_values([goal_message.v, goal_message.w, goal_message.d,
                                         goal_message.T, goal_message.psi])
        if self.layer.safety.active:
            self.output.halt('safety')
            return 'aborted', BackTravelResult(), 'safety stop: %s' % ', '.join(self.layer.safety.active)
        odom = self.odometry.fresh(p.odom_timeout) or self._wait_for_odometry()
        if odom is None:
            self.output.halt('odometry')
            return 'aborted', BackTravelResult(), self.odometry.describe_missing(p.odom_timeout)
        self.output.limit(self.follower.limits[self.next_goal] if self.follower is not None
                          else goal_limits(landmark, p.max_v, p.max_w, p.correction_w))
        self.output.release()
        goal = make_goal(p.control, landmark, self.goal_params, self.follower, self.next_goal)
        goal.start(odom)
        started = odom.stamp
        result = lambda: BackTravelResult(distance=goal.travelled, duration=rospy.get_time() - started)
        grace = OdomGrace(p)
        rate = rospy.Rate(p.control_rate)
        next_feedback = started
        while not goal.done:
            if self._tripped:
                self.output.halt('safety')
                return 'aborted', result(), 'safety stop: %s after %.3f m' % (self._tripped,
                                                                              goal.travelled)
            if self._cancelled(handle) or rospy.is_shutdown():
                self.output.halt('cancel')
                return 'canceled', result(), 'canceled after %.3f m' % goal.travelled
            if self.layer.mission.state != mission_state.RETURNING:
                return 'aborted', result(), 'the mission is %s' % self.layer.mission.state
            now, age = rospy.get_time(), self.odometry.age()
            decision, message = grace.check(now, None if age is None else now - age)
            if message:
                (self.log.error if decision == ABORT else self.log.warn)('goal %d: %s',
                                                                        self.next_goal + 1, message)
            if decision == ABORT:
                self.output.halt('odometry')
                return 'aborted', result(), '%s (%s)' % (
                    message, self.odometry.describe_missing(p.odom_timeout))
            if decision == HOLD:
                self.output.stop()
                self._sleep(rate)
                continue
            odom = self.odometry.fresh(p.odom_timeout)
            v, w = goal.step(odom)
            if goal.failed:
                self.output.halt('no progress')
                return 'aborted', result(), goal.reason
            if goal.done:
                break
            self.output.publish(v, w)
            self.hold.published(now)
            if odom.stamp >= next_feedback:
                handle.publish_feedback(BackTravelFeedback(distance=goal.travelled))
                next_feedback = odom.stamp + 1.0 / p.feedback_rate
            self._sleep(rate)
        self._report_late()
        return 'succeeded', result(), ''

    def _report_late(self):
        """Log the sections that took longer than their nominal time (not a failure)."""
        if self.follower is not None:
            while self.follower.late:
                index, taken, nominal = self.follower.late.pop(0)
                self.log.warn('goal %d took %.1f s, nominally %.1f s (logged, not a failure: the '
                              'return stops only when it stops making progress)',
                              index + 1, taken, nominal)

    @staticmethod
    def _sleep(rate):
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            pass

"""The back-travel server: the paper's action server (3.3.5-3.3.6).

Serves ``blind_navigation/back_travel``: one landmark per goal, driven in the mode
``control`` (core/goal.py) on the route the owner set (``set_return_route``); only the
owner's goals, while ``returning``, the route's next one. Commands go through
ros/motion.MotionOutput; odometry grace, contacts and takeovers hold a goal, a cliff
or wheel drop aborts it (docs/back_travel.md, docs/safety.md).
"""
import threading
import types

import actionlib
import rospy

from blind_navigation import names
from blind_navigation.core import drive, mission_state
from blind_navigation.core.allowance import OdomGrace
from blind_navigation.core.route_follower import RouteFollower
from blind_navigation.core.geometry import distance
from blind_navigation.core.goal import CommandHold, bridges, make_goal
from blind_navigation.core.landmark import landmark_from_values
from blind_navigation.core.pause import Contacts
from blind_navigation.core.safety import goal_limits, landmarks_from_flat
from blind_navigation.core.role_params import BACK_TRAVEL_SERVER
from blind_navigation.core.segment import period_of
from blind_navigation.msg import BackTravelAction, BackTravelFeedback, BackTravelResult
from blind_navigation.ros import diagnostics
from blind_navigation.ros.clock import action_server, after
from blind_navigation.ros.common import shutting_down
from blind_navigation.ros.drive_loop import DriveLoop
from blind_navigation.ros.faults import describe
from blind_navigation.ros.handover_bridge import drive_between_goals, wait_while
from blind_navigation.ros.motion import MotionOutput
from blind_navigation.ros.route_wire import route_of
from blind_navigation.srv import SetReturnRoute, SetReturnRouteResponse


class BackTravelServer(object):
    """Drives one landmark per goal (module docstring)."""

    ROLE = mission_state.BACK_TRAVEL_ROLE
    SCHEMA = BACK_TRAVEL_SERVER

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.SCHEMA)
        self.log = layer.logger(self.ROLE)
        for name in ('control_rate', 'feedback_rate', 'handover_timeout', 'route_max_offset',
                     'status_frequency'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        OdomGrace(p)                     # validates the odometry params now
        self.contacts = Contacts(p)      # the return's bumper contacts (validates their params)
        layer.safety.contact_wait = p.contact_wait     # its bounces log once per contact
        self.straight_period = period_of(p.straight_rate, '~straight_rate')
        self.goal_params = types.SimpleNamespace(**dict(
            p._asdict(), straight_period=self.straight_period))
        self.layer = layer
        self.odometry = layer.odometry
        self.takeover = layer.takeover(p)
        self.output = MotionOutput(self.ROLE, p.max_v, p.max_w, layer.mission, layer.safety,
                                   self.takeover)
        layer.heading_correction()       # drive on the corrected odometry once it exists
        self._lock = threading.Lock()
        self._active = None              # the goal handle being driven
        self._pending = None             # the accepted goal handle waiting for the worker
        self._wake = threading.Event()
        self.hold = CommandHold(p.handover_timeout)   # the output between goals
        self.route = None                # core Route of the return
        self.landmarks = []              # its goals' landmarks, return order
        self.next_goal = 0               # index of the goal the route expects next
        self.follower = None             # closed_loop: the RouteFollower of the return
        self.since = None                # its travelled when the last goal ended (core/goal.SectionGoal)
        self._bridging, self.bridge_failed = False, None   # a HandoverBridge drives; what ended it
        guard = self.guard = layer.guard(self.ROLE)
        self.drive = DriveLoop(self.output, self.odometry, layer.safety, p, self.log, guard,
                               takeover=self.takeover)
        layer.mission.on_change(guard(self._on_state))
        rospy.Service(names.SET_RETURN_ROUTE, SetReturnRoute, guard(self._on_set_route))
        self.server = action_server(names.BACK_TRAVEL, BackTravelAction, guard, self._on_goal,
                                    self._on_cancel, 1.0 / p.status_frequency, self.log)
        rospy.on_shutdown(self._wake.set)
        threading.Thread(target=guard(self._work), name='back_travel_goals', daemon=True).start()
        self.last_abort = ''
        layer.diagnostics.add('back travel', self._diagnose)
        self.log.info('serving %s in %s mode on %s', rospy.resolve_name(names.BACK_TRAVEL),
                      p.control, rospy.resolve_name(names.CMD_VEL))

    # --- who may send what -------------------------------------------------------------------
    def _on_set_route(self, request):
        """The return's route, its goals' landmarks and how many are done."""
        wait_while(lambda: self._bridging, self.params.handover_follow + 1.0)  # a client restarted
        try:
            route, landmarks = self._read_route(request)
        except ValueError as error:
            self.log.error('return route refused: %s', error)
            return SetReturnRouteResponse(ok=False, message=str(error), control=self.params.control)
        with self._lock:
            if self._active is not None or self._pending is not None or self._bridging:
                return SetReturnRouteResponse(ok=False, message='a goal is being driven',
                                              control=self.params.control)
            self.route, self.landmarks, self.next_goal = route, landmarks, request.completed
            self.contacts = Contacts(self.params)      # counted over the whole return
            self.follower = RouteFollower(route, self.goal_params) \
                if self.params.control == 'closed_loop' else None
            self.since = self.bridge_failed = None
        self.log.info('return route of %d landmarks (%.2f m) in %s, %d completed',
                      len(landmarks), route.length, request.header.frame_id or '?', request.completed)
        closed = self.params.control == 'closed_loop'
        return SetReturnRouteResponse(ok=True, message='', control=self.params.control,
                                      home_tolerance=self.params.home_tolerance if closed else 0.0)

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
        self.odometry.acquire(self.ROLE)
        odom = self.odometry.wait_fresh(self.params.odom_timeout, self.params.odom_grace)
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
            # actionlib's ServerGoalHandle.__eq__ raises on None: compare only with a goal held
            ours = any(held is not None and held == handle for held in (self._active, self._pending))
        if ours or self._bridging:      # between goals too: the follower drives on meanwhile
            self.output.halt('cancel')  # at once, not at the next control cycle

    def _on_state(self, _old, new):
        if new == mission_state.RETURNING:
            self.odometry.acquire(self.ROLE)
        elif new in mission_state.TERMINAL:
            self.odometry.release(self.ROLE)

    def _diagnose(self, stat):
        stat.add('control', self.params.control)
        stat.add('goals done', '%d of %d' % (self.next_goal, len(self.landmarks)))
        stat.add('bumper contacts', self.contacts.describe())
        stat.add('takeover', self.takeover.active() or 'none')
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
            after(remaining, self.guard(self._on_handover_timeout), 'hand-over', self.log)
        else:
            self._on_handover_timeout()

    def _on_handover_timeout(self):
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
            self.execute(handle)

    def execute(self, handle):
        try:
            outcome, result = self._run(handle)
        except Exception as error:  # never leave the robot moving or the goal hanging
            self.layer.faults.fail(self.ROLE, error, 'BackTravelServer._run')
            outcome, result = drive.Outcome(drive.FAILED, describe(self.ROLE, error)), BackTravelResult()
        if outcome.kind not in (drive.SUCCEEDED, drive.CANCELLED):
            self.log.error('goal aborted: %s', outcome.reason)
            self.last_abort = outcome.reason
        follower = self.follower
        with self._lock:
            self._active = None
            if outcome.ok:
                self.next_goal += 1
            bridge = outcome.ok and bridges(self.params.control, follower, self.next_goal,
                                            len(self.landmarks), self.params.handover_follow)
            self._bridging = bridge
            self.since = follower.travelled if bridge else None
        if outcome.ok and not bridge:
            self._schedule_handover()
        end = {drive.SUCCEEDED: handle.set_succeeded, drive.CANCELLED: handle.set_canceled}
        end.get(outcome.kind, handle.set_aborted)(_coded(result, outcome), outcome.reason)
        if bridge:
            drive_between_goals(self, follower)

    def _run(self, handle):
        """Drive one goal; returns (core/drive.Outcome with the result's text, result)."""
        failed, self.bridge_failed = self.bridge_failed, None
        if failed is not None:          # what ended the hand-over before it ends this goal
            return failed, BackTravelResult()
        p = self.params
        goal_message = handle.get_goal()
        landmark = landmark_from_values([goal_message.v, goal_message.w, goal_message.d,
                                         goal_message.T, goal_message.psi])
        self.output.limit(self.follower.limits[self.next_goal] if self.follower is not None
                          else goal_limits(landmark, p.max_v, p.max_w, p.correction_w))
        self.odometry.acquire(self.ROLE)
        goal = _Goal(make_goal(p.control, landmark, self.goal_params, self.follower, self.next_goal,
                               self.since), handle, self.hold, p.feedback_rate)
        outcome = self.drive.run(goal, 'goal %d' % (self.next_goal + 1), wait=p.odom_grace,
                                 cancelled=goal.cancelled, inactive=self._inactive,
                                 contacts=self.contacts)
        if outcome.ok:
            _report_late(self.follower, self.log)
        return goal.ended(outcome)

    def _inactive(self):
        return None if self.layer.mission.state == mission_state.RETURNING else \
            'the mission is %s' % self.layer.mission.state


def _coded(result, outcome):
    """``result`` (a BackTravelResult) carrying the core/outcome code of ``outcome`` (the
    goal's core/drive.Outcome): the client ends the mission with it."""
    result.outcome = outcome.cause
    return result


def _report_late(follower, log):
    """Log the sections that took longer than their nominal time (not a failure)."""
    while follower is not None and follower.late:
        index, taken, nominal = follower.late.pop(0)
        log.warn('goal %d took %.1f s, nominally %.1f s (logged, not a failure: the return stops '
                 'only when it stops making progress)', index + 1, taken, nominal)


class _Goal(drive.Behaviour):
    """One back-travel goal as a drive-loop behaviour: its core/goal, feedback, the hold."""

    def __init__(self, goal, handle, hold, feedback_rate):
        self.goal, self.handle, self.command_hold = goal, handle, hold
        self.period = 1.0 / feedback_rate
        self.started = self.next_feedback = None

    def start(self, odom):
        self.goal.start(odom)
        self.started = self.next_feedback = odom.stamp

    def end(self):
        return drive.Outcome(drive.SUCCEEDED, '') if self.goal.done else None

    def hold(self, seconds):
        self.goal.hold(seconds)

    def resumed(self, seconds):
        self.goal.resumed(seconds)

    def step(self, odom, now):
        v, w = self.goal.step(odom)
        if self.goal.failed:
            return drive.Outcome(drive.FAILED, self.goal.reason, self.goal.code)
        if self.goal.done:
            return drive.Outcome(drive.SUCCEEDED, '')
        self.command_hold.published(now)
        if odom.stamp >= self.next_feedback:
            self.handle.publish_feedback(BackTravelFeedback(distance=self.goal.travelled))
            self.next_feedback = odom.stamp + self.period
        return v, w

    def cancelled(self):
        return self.handle.get_goal_status().status in (actionlib.GoalStatus.PREEMPTING,
                                                        actionlib.GoalStatus.RECALLING)

    def ended(self, outcome):
        """``(outcome with the result's text, result)`` of the goal's ``outcome``."""
        if outcome.kind == drive.SAFETY_STOP:
            outcome = outcome._replace(reason='safety stop: ' + outcome.reason)
        if self.started is None:
            return outcome, BackTravelResult()
        travelled = self.goal.travelled
        result = BackTravelResult(distance=travelled, duration=rospy.get_time() - self.started)
        if outcome.kind == drive.SAFETY_STOP:
            outcome = outcome._replace(reason='%s after %.3f m' % (outcome.reason, travelled))
        elif outcome.kind == drive.CANCELLED:
            outcome = outcome._replace(reason='canceled after %.3f m' % travelled)
        return outcome, result

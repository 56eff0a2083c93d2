"""The back-travel server (paper 3.3.5-3.3.6): one landmark per ``back_travel`` goal of the
route the owner set (``set_return_route``), driven by the mission's ReturnDrive on a DriveNode;
only the owner's goals, while ``returning``, the route's next one (docs/back_travel.md).
"""
import threading
import types

import actionlib
import rospy
from actionlib_msgs.msg import GoalID

from blind_navigation import names
from blind_navigation.core import drive, mission_state
from blind_navigation.core.allowance import OdomGrace
from blind_navigation.core.geometry import distance
from blind_navigation.core.landmark import landmark_from_values
from blind_navigation.core.mission_drive import FINAL, GOAL, HANDOVER, ZERO, ReturnDrive
from blind_navigation.core.pause import Contacts
from blind_navigation.core.role_params import BACK_TRAVEL_SERVER
from blind_navigation.core.route import Route, route_lists
from blind_navigation.core.route_follower import RouteFollower
from blind_navigation.core.safety import goal_limits, landmarks_from_flat
from blind_navigation.core.segment import period_of
from blind_navigation.msg import BackTravelAction, BackTravelFeedback, BackTravelResult, ReturnRoute
from blind_navigation.ros import diagnostics
from blind_navigation.ros.clock import action_server
from blind_navigation.ros.drive_node import DriveNode
from blind_navigation.ros.mission import Role
from blind_navigation.srv import SetReturnRoute, SetReturnRouteResponse

#: The client watches the whole return; the server's goals: none.
UNWATCHED = types.SimpleNamespace(problem=lambda now, travelled: None, resumed=lambda seconds: None)


class BackTravelServer(Role):
    """Drives one landmark per goal (module docstring)."""

    ROLE = mission_state.BACK_TRAVEL_ROLE
    SCHEMA = BACK_TRAVEL_SERVER

    def __init__(self, layer):
        Role.__init__(self, layer)
        p = self.params
        OdomGrace(p), Contacts(p)        # validates the odometry's and the contacts' params now
        layer.safety.contact_wait = p.contact_wait     # its bounces log once per contact
        self.goal_params = types.SimpleNamespace(**dict(
            p._asdict(), straight_period=period_of(p.straight_rate, '~straight_rate'),
            await_goals=True))
        self.odometry = layer.odometry
        layer.heading_correction()       # drive on the corrected odometry once it exists
        self.driver = DriveNode(self, (p.max_v, p.max_w), layer.mission, True, self._label)
        self.output = self.driver.output
        self._lock = threading.RLock()      # re-entered: _busy() while setting a route
        self.follower = self.drive = None   # the return's RouteFollower (closed_loop), ReturnDrive
        self.landmarks = []             # its goals' landmarks, return order
        self.active = self.pending = None   # the goal handle driven; accepted, waiting
        self.ended = None               # the core/drive.Outcome that ended the return, if any
        self.started = self.feedback_at = self.pending_since = self.odom = self.index = None
        self.last_abort = ''
        self.follow('back travel')
        rospy.Service(names.SET_RETURN_ROUTE, SetReturnRoute, self.guard(self._on_set_route))
        self.server = action_server(names.BACK_TRAVEL, BackTravelAction, self.guard, self._on_goal,
                                    self._on_cancel, 1.0 / p.status_frequency, self.log)
        # actionlib passes a cancel of every goal to the goals it finds; between two there is none
        rospy.Subscriber(names.BACK_TRAVEL + '/cancel', GoalID, self.guard(self._on_cancel_every),
                         queue_size=10)
        self.log.info('serving %s in %s mode on %s', rospy.resolve_name(names.BACK_TRAVEL),
                      p.control, rospy.resolve_name(names.CMD_VEL))

    def _on_set_route(self, request):
        """The return's route, its goals' landmarks and how many are done."""
        p = self.params
        try:
            route, landmarks = self._read_route(request)
        except ValueError as error:
            self.log.error('return route refused: %s', error)
            return SetReturnRouteResponse(ok=False, message=str(error), control=p.control)
        with self._lock:
            if self.active is not None or self.pending is not None:
                return SetReturnRouteResponse(ok=False, message='a goal is being driven', control=p.control)
            if self._busy():
                self.output.stop()      # a hand-over under way ends here
            self.landmarks, self.ended = landmarks, None
            self.follower = RouteFollower(route, self.goal_params) if p.control == 'closed_loop' else None
            self.drive = ReturnDrive(list(enumerate(landmarks)), p.control, self.goal_params,
                                     self.follower, self.goal_params, self.driver.feed,
                                     lambda: self.odom, UNWATCHED)
            self.drive.index = request.completed
            self.driver.start(self.drive)   # contacts counted over the whole return
        self.log.info('return route of %d landmarks (%.2f m) in %s, %d completed',
                      len(landmarks), route.length, request.header.frame_id or '?', request.completed)
        return SetReturnRouteResponse(ok=True, message='', control=p.control, home_tolerance=p.home_tolerance
                                      if p.control == 'closed_loop' else 0.0)

    def _read_route(self, request):
        """(Route, landmarks) of a SetReturnRoute request; ValueError naming what is wrong."""
        refused = self._refusal(request._connection_header.get('callerid', '?'),
                                'sets the return route')
        if refused:
            raise ValueError(refused)
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
            self.pending, self.pending_since = handle, rospy.get_time()
        handle.set_accepted()
        self.driver.wake.set()

    def _goal_problem(self, handle):
        """Why a goal is rejected, or None."""
        refused = self._refusal(handle.goal._connection_header.get('callerid', '?') if handle.goal
                                else '?', 'sends back-travel goals')
        if refused:
            return refused
        goal = handle.get_goal()
        values = [goal.v, goal.w, goal.d, goal.T, goal.psi]
        try:
            landmark = landmark_from_values(values)
        except ValueError as error:
            return 'bad goal %r: %s' % (values, error)
        with self._lock:
            if self.active is not None or self.pending is not None:
                return 'a goal is being driven (one at a time)'
            if self.drive is None:
                return 'no return route set (%s)' % rospy.resolve_name(names.SET_RETURN_ROUTE)
            if self.drive.index >= len(self.landmarks):
                return 'the route has no goal left (%d done)' % self.drive.index
            index, expected = self.drive.index, self.landmarks[self.drive.index]
        if tuple(landmark) != tuple(expected):
            return 'not the next landmark of the route (goal %d expects %r)' % (index + 1, list(expected))
        return None

    def _refusal(self, sender, sends):
        """Why ``sender``'s request is refused (the mission not returning, not its owner)."""
        state = self.layer.mission.state
        if state != mission_state.RETURNING:
            return 'the mission is %s, not returning' % state
        if sender != self.layer.mission_owner:
            return 'only %s %s, not %s' % (self.layer.mission_owner, sends, sender)
        return None

    def _on_cancel(self, handle):
        with self._lock:
            # actionlib's ServerGoalHandle.__eq__ raises on None: compare only with a goal held
            ours = any(held is not None and held == handle for held in (self.active, self.pending))
            bridging = self.drive is not None and self.drive.phase == HANDOVER and self.drive.bridge is not None
        if ours or bridging:            # between goals too: the follower drives on meanwhile
            self.output.halt('cancel')  # at once, not at the next control cycle

    def _on_cancel_every(self, msg):
        """A cancel of every goal (empty id) with no goal held ends the return under way: the
        hand-over's command stops and the route's later goals end cancelled."""
        with self._lock:
            d = self.drive
            between = (not msg.id and self.active is None and self.pending is None and d is not None
                       and self.ended is None and d.index < len(self.landmarks))
            if between:
                self.ended = drive.Outcome(drive.CANCELLED, 'cancelled between goals %d and %d'
                                           % (d.index, d.index + 1))
        if between:
            self.output.halt('cancel')
            self.log.warn('every goal cancelled between goals %d and %d: the return stops',
                          d.index, d.index + 1)

    def _on_state(self, _old, new):
        if new == mission_state.RETURNING:
            self.odometry.acquire(self.ROLE)
        elif new in mission_state.TERMINAL:
            self.odometry.release(self.ROLE)

    def _diagnose(self, stat):
        stat.add('control', self.params.control)
        stat.add('goals done', '%d of %d' % (self.drive.index if self.drive else 0, len(self.landmarks)))
        stat.add('bumper contacts', self.driver.pauses.contacts.describe() if self.driver.pauses else 'none')
        self.driver.diagnose(stat)
        if self.layer.mission.state == mission_state.RETURNING:
            diagnostics.age_status(stat, 'odometry', self.odometry.age(), self.params.odom_timeout,
                                   diagnostics.ERROR, listening=self.odometry.listening())
        elif self.last_abort:
            stat.summary(diagnostics.ERROR, 'last goal aborted: %s' % self.last_abort)
        else:
            stat.summary(diagnostics.OK, 'ready' if self.drive is None else 'route set')

    def run(self):
        """Step the return while a goal, a hand-over or the final hold is under way."""
        for now, jump in self.driver.ticks(self._busy):
            handle = self.active        # actionlib's calls outside the lock (its callbacks take it)
            cancelled = handle is not None and handle.get_goal_status().status in (
                actionlib.GoalStatus.PREEMPTING, actionlib.GoalStatus.RECALLING)
            with self._lock:
                calls = self._step(now, jump, cancelled and handle is self.active)
            for call in calls:
                call()

    def _busy(self):
        with self._lock:
            d = self.drive
            return self.pending is not None or (d is not None and self.ended is None and (
                self.active is not None or d.phase == FINAL
                or d.phase == HANDOVER and d.command != ZERO))

    def _label(self):
        d = self.drive
        return 'goal %d' % (d.index + 1) if d.phase == GOAL else 'hand-over after goal %d' % d.index

    def _step(self, now, jump, cancelled):
        """This cycle: the goal's start, the drive's step, the goal's end; the handle's calls."""
        p, d, next_goal = self.params, self.drive, False
        if self.active is None and self.pending is not None:
            self.odom = self.odometry.fresh(p.odom_timeout)
            if self.ended is None and self.odom is None and now - self.pending_since < p.odom_grace:
                return []               # a goal starts on fresh odometry
            self.active, self.pending, self.started, self.feedback_at = self.pending, None, now, now
            if self.ended is not None or self.odom is None:
                return [self._end(self.ended or drive.Outcome(drive.ODOMETRY_LOST, 'cannot start: %s' % (
                    self.odometry.describe_missing(p.odom_timeout))), now, 0.0)]
            self.index, next_goal = d.index, True
            self.output.limit(self.follower.limits[d.index] if self.follower is not None
                              else goal_limits(self.landmarks[d.index], p.max_v, p.max_w, p.correction_w))
        elif d.phase == HANDOVER and d.bridge is not None:
            self.output.limit(self.follower.limits[min(self.follower.section, len(self.landmarks) - 1)])
        state = self.layer.mission.state
        ended = self.driver.step(now, jump, cancelled, None if state == mission_state.RETURNING
                                 else 'the mission is %s' % state, next_goal)
        calls = []
        if self.active is not None and d.index > self.index:
            calls.append(self._end(drive.Outcome(drive.SUCCEEDED, ''), now, d.goal.travelled))
            while self.follower is not None and self.follower.late:
                late, taken, nominal = self.follower.late.pop(0)
                self.log.warn('goal %d took %.1f s, nominally %.1f s (logged, not a failure: the '
                              'return stops only when it stops making progress)', late + 1, taken,
                              nominal)
        elif self.active is not None and d.phase == GOAL and now >= self.feedback_at:
            handle, travelled = self.active, d.goal.travelled
            calls.append(lambda: handle.publish_feedback(BackTravelFeedback(distance=travelled)))
            self.feedback_at = now + 1.0 / p.feedback_rate
        if ended is not None:
            self.ended = ended          # a later goal of this return ends with it
            calls += [self._end(ended, now, d.goal.travelled if d.phase != HANDOVER else 0.0)] \
                if self.active is not None else []
        return calls

    def _end(self, ended, now, travelled):
        """The call that ends the active goal's handle with ``ended`` after ``travelled`` m."""
        handle, self.active = self.active, None
        result = BackTravelResult(distance=travelled, duration=now - self.started, outcome=ended.cause)
        reason = ended.reason
        if ended.kind == drive.SAFETY_STOP:
            reason = '%s after %.3f m' % (reason, travelled)
        elif ended.kind == drive.CANCELLED:
            reason = 'canceled after %.3f m' % travelled
        elif ended.kind != drive.SUCCEEDED:
            self.log.error('goal aborted: %s', reason)
            self.last_abort = reason
        end = {drive.SUCCEEDED: handle.set_succeeded, drive.CANCELLED: handle.set_canceled}
        return lambda: end.get(ended.kind, handle.set_aborted)(result, reason)


def route_of(request):
    """The core/route.Route a SetReturnRoute request carries; ValueError naming a bad field."""
    msg = request.route
    if msg.version != ReturnRoute.ROUTE_VERSION:
        raise ValueError('route: version %d, this server reads version %d' % (msg.version, ReturnRoute.ROUTE_VERSION))
    try:
        return Route.from_lists(route_lists(msg))
    except ValueError as error:
        raise ValueError('route: %s' % error)

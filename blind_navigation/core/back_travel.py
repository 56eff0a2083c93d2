"""Back-travel control: drive the recorded path back to the start (paper 3.3.5).

Three modes (docs/back_travel.md, "Control modes"):

- ``time``: the paper's sampled-time control, one :class:`TimeController` per
  goal: the landmark's ``(v, -w)`` for its period ``T``.
- ``distance``: the paper's travelled-distance control
  (:class:`DistanceController`): the same commands until odometry shows ``d``.
- ``closed_loop``: :class:`RouteFollower` drives the whole route
  (core/route.build_route): pure pursuit between corners, a turn in place at
  each corner, at the recorded speed and never faster (:func:`section_limits`).

One goal interface for both kinds (core/goal.make_goal); docs/back_travel.md.
"""
import math

from types import SimpleNamespace

from .allowance import ProgressWatch
from .geometry import distance, wrap_angle
from .landmark import Landmark
from .rotation import ROTATION_DEFAULTS, Rotation
from .safety import SAFETY_DEFAULTS, VelocityLimits, goal_limits

MODES = ('time', 'distance', 'closed_loop')

#: Defaults; the back_travel_server node exposes each one as a ~private param.
BACK_TRAVEL_DEFAULTS = {
    'straight_period': 2.0,   # s; a landmark with T >= this is a straight segment
    'max_v': 0.5,             # m/s, hard clamp on |v|
    'max_w': 1.0,             # rad/s, hard clamp on |w|
    'timeout_factor': 3.0,    # a goal's allowance = factor * expected duration + timeout_margin
    'timeout_margin': 2.0,    # s added to a goal's allowance
    'lookahead': 0.1,         # m, shortest pure-pursuit lookahead (closed_loop)
    'min_v': 0.03,            # m/s, slowest speed of distance goals, and of closed-loop sections recorded faster
    'creep_v': 0.02,          # m/s; a stretch recorded slower is driven at this (closed_loop; slower,
                              # the base's own wheel-speed ripple stalls it)
    'min_d': 0.002,           # m, goals shorter than this end at once (distance)
    'stop_lead': 0.2,         # s the robot coasts after its last command (closed_loop)
    'lookahead_time': 0.5,    # s; the lookahead grows to this x the speed (closed_loop)
    'brake_decel': 0.5,       # m/s^2; slowing down towards a corner and the end (closed_loop)
    'stopped_v': 0.01,        # m/s; below this (and stopped_w) the robot counts as stopped
    'stopped_w': 0.05,        # rad/s; below this (and stopped_v) the robot counts as stopped
    'stop_timeout': 2.0,      # s; the longest wait for the robot to stop at a corner
    'align_tolerance': 0.1,   # rad; a smaller heading error at a corner is left to the pursuit
    'aim_distance': 0.1,      # m; a turn in place faces the route point this far ahead
    'correction_w': SAFETY_DEFAULTS['correction_w'],  # rad/s a section may turn beyond its recorded rate
}


def _param(params, name):
    return float(getattr(params, name, BACK_TRAVEL_DEFAULTS[name]))


def _clamp(value, limit):
    return max(-limit, min(limit, value))


def is_straight(landmark, straight_period):
    """True when the landmark was sampled at the straight (longer) period."""
    return landmark.T >= straight_period - 1e-6


def replay_command(landmark, straight_period):
    """The paper's back-travel command for ``landmark``: ``(v, 0)`` on straight
    segments, ``(v, -w)`` on curved ones (turn mirrored, see module docstring)."""
    if is_straight(landmark, straight_period):
        return landmark.v, 0.0
    return landmark.v, -landmark.w


class _Controller(object):
    """Common bookkeeping: odometry distance, time allowance, clamping."""

    def __init__(self, landmark, params):
        self.landmark = landmark
        self.max_v = _param(params, 'max_v')
        self.max_w = _param(params, 'max_w')
        self.straight_period = _param(params, 'straight_period')
        self.allowance = (_param(params, 'timeout_factor') * self.expected_duration(params)
                          + _param(params, 'timeout_margin'))
        self.travelled = 0.0
        self.done = False
        self.failed = False
        self.started = None
        self._last = None

    def expected_duration(self, params):
        return self.landmark.T

    def elapsed(self, odom_state):
        return odom_state.stamp - self.started

    def start(self, odom_state):
        self.started = odom_state.stamp
        self._last = odom_state
        self.travelled = 0.0
        self.done = self.failed = False

    def step(self, odom_state):
        if self.started is None:
            raise RuntimeError('%s.step called before start' % type(self).__name__)
        self.travelled += distance(self._last.x, self._last.y, odom_state.x, odom_state.y)
        self._last = odom_state
        if self.done or self.failed:
            return 0.0, 0.0
        if self.elapsed(odom_state) > self.allowance:
            self.failed = True
            return 0.0, 0.0
        v, w = self.command(odom_state)
        if self.done:
            return 0.0, 0.0
        return _clamp(v, self.max_v), _clamp(w, self.max_w)

    def command(self, odom_state):
        raise NotImplementedError


class TimeController(_Controller):
    """The paper's sampled-time control: the replayed velocity for ``T`` seconds."""

    def command(self, odom_state):
        if self.elapsed(odom_state) >= self.landmark.T - 1e-9:
            self.done = True
        return replay_command(self.landmark, self.straight_period)


class DistanceController(_Controller):
    """The paper's travelled-distance control: the replayed velocity until ``d``.

    A landmark taken while the robot was stopping can carry ``v`` near 0 with
    ``d`` > 0, which could never be covered: ``|v|`` is raised to ``min_v``
    (sign kept). Goals with ``d < min_d`` end at once.
    """

    def __init__(self, landmark, params):
        self.min_v = _param(params, 'min_v')
        super(DistanceController, self).__init__(landmark, params)
        v, self.w_command = replay_command(landmark, self.straight_period)
        self.v_command = math.copysign(max(abs(v), self.min_v), v)
        self.min_d = _param(params, 'min_d')

    def expected_duration(self, params):
        return max(self.landmark.T, self.landmark.d / max(abs(self.landmark.v), self.min_v))

    def command(self, odom_state):
        if self.travelled >= self.landmark.d or self.landmark.d < self.min_d:
            self.done = True
        return self.v_command, self.w_command


def make_controller(mode, landmark, params=None):
    """The paper-mode controller of one landmark (``time`` or ``distance``);
    ``closed_loop`` goals are sections of one :class:`RouteFollower`
    (core/goal.make_goal)."""
    if mode == 'time':
        return TimeController(landmark, params)
    if mode == 'distance':
        return DistanceController(landmark, params)
    if mode == 'closed_loop':
        raise ValueError('closed_loop goals are sections of one RouteFollower (core/goal.make_goal), '
                         'not a per-landmark controller')
    raise ValueError('unknown back-travel mode %r (expected one of %s)' % (mode, ', '.join(MODES)))


# --- closed loop: the whole route ------------------------------------------------
DRIVING, STOPPING, TURNING, FINISHED = 'driving', 'stopping', 'turning', 'finished'


def section_limits(section, max_v, max_w, correction_w, creep_v):
    """core/safety.goal_limits of a route section: never faster than its recorded
    speed, never turning faster than its recorded turn rate + ``correction_w``;
    but a stretch recorded slower than ``creep_v`` (at most a few centimetres:
    d / T is below it) may be driven at ``creep_v``."""
    limits = goal_limits(Landmark(section.speed, section.turn_rate, 0.0, 1.0, 0.0),
                         max_v, max_w, correction_w)
    return limits._replace(max_v=max(limits.max_v, min(creep_v, max_v)))


class RouteFollower(object):
    """Drives a core/route.Route from its anchor to its end (module docstring).

    Modes: ``driving`` a piece (pure pursuit), ``stopping`` at a corner,
    ``turning`` in place there (core/rotation.Rotation to the heading of the
    route point ``aim_distance`` ahead), ``finished``. ``params``: attributes
    of :data:`BACK_TRAVEL_DEFAULTS`, core/allowance.ALLOWANCE_DEFAULTS and
    core/rotation.ROTATION_DEFAULTS (gain, decel, min_w, tolerance; missing
    ones take the defaults).
    """

    def __init__(self, route, params=None):
        self.route = route
        self.params = params
        for name in ('max_v', 'max_w', 'lookahead', 'min_v', 'stop_lead', 'lookahead_time',
                     'brake_decel', 'stopped_v', 'stopped_w', 'stop_timeout', 'align_tolerance',
                     'aim_distance', 'correction_w', 'timeout_factor', 'timeout_margin', 'creep_v'):
            setattr(self, name, _param(params, name))
        self.limits = [section_limits(sec, self.max_v, self.max_w, self.correction_w, self.creep_v)
                       for sec in route.sections]
        self.nominal = [sec.nominal_time + abs(sec.turn) / max(limit.max_w, 1e-3)
                        for sec, limit in zip(route.sections, self.limits)]
        self.watch = ProgressWatch(sum(self.nominal), params)
        self.done = self.failed = False
        self.reason = ''
        self.mode = None
        self.section = 0
        self.late = []
        self.travelled = 0.0
        self._mark = (0.0, 0.0)       # progress: (s along the route, phase of the corner turn)
        self._piece = 0
        self._segment = 0
        self._target = None           # the last pursuit target: (x, y, segment) on the current piece
        self._rotation = None
        self._turn_angle = 0.0
        self._last = None
        self._stop_since = None
        self._section_started = 0.0

    # --- progress ---------------------------------------------------------------
    @property
    def started(self):
        """True once :meth:`start` was called."""
        return self._last is not None

    @property
    def progress(self):
        """(m along the route, phase of the turn at the corner there)."""
        return self._mark

    def section_finished(self, index):
        """Whether section (goal) ``index`` of the route is done."""
        return self.done or self._mark >= self.route.section_end(index)

    def _advance(self, mark):
        """Move the progress mark forward (never back) and close finished sections."""
        if mark > self._mark:
            self._mark = mark
        sections = self.route.sections
        while self.section < len(sections) and self._mark >= self.route.section_end(self.section):
            taken = self.watch.active - self._section_started
            allowed = self.timeout_factor * self.nominal[self.section] + self.timeout_margin
            if taken > allowed:
                self.late.append((self.section, taken, self.nominal[self.section]))
            self._section_started = self.watch.active
            self.section += 1

    def _limit(self):
        if not self.limits:
            return VelocityLimits(min(self.creep_v, self.max_v), min(self.correction_w, self.max_w))
        return self.limits[min(self.section, len(self.limits) - 1)]

    # --- control ----------------------------------------------------------------
    def start(self, odom_state, section=0):
        """Start (or resume at goal ``section``) from ``odom_state``."""
        route = self.route
        if not 0 <= section <= len(route.sections):
            raise ValueError('cannot start at section %d of %d' % (section, len(route.sections)))
        self._last = odom_state
        self.travelled = 0.0
        self.done = self.failed = False
        self.reason = ''
        self.watch.update(odom_state.stamp, 0.0)
        mark = (0.0, 0.0) if section == 0 else route.section_end(section - 1)
        vertex = 0 if section == 0 else route.sections[section - 1].end_vertex
        self._mark = mark
        self.section = section
        self._section_started = self.watch.active
        self._advance(mark)
        if route.vertices == 1 or vertex >= route.vertices - 1:
            self._finish()
            return
        self._piece = route.piece_of(vertex)
        self._segment = vertex
        self._target = None
        if route.corner[vertex] and mark[1] < 1.0:
            self._start_turn(odom_state)
        else:
            self.mode = DRIVING

    def step(self, odom_state):
        """(v, w) for this control cycle; sets done / failed (then (0, 0))."""
        if self._last is None:
            raise RuntimeError('RouteFollower.step called before start')
        self.travelled += distance(self._last.x, self._last.y, odom_state.x, odom_state.y)
        self._last = odom_state
        if self.done or self.failed:
            return 0.0, 0.0
        if self.mode == DRIVING:
            command, heading_error = self._drive(odom_state)
        elif self.mode == STOPPING:
            command, heading_error = self._stop(odom_state), None
        else:
            command, heading_error = self._turn(odom_state)
        why = self.watch.update(odom_state.stamp, self._mark[0], heading_error)
        if why and not self.done:
            self.failed, self.reason = True, why
        if self.done or self.failed:
            return 0.0, 0.0
        return self._limit().clamp(*command)

    def _finish(self):
        self.mode = FINISHED
        self._advance((self.route.length, 1.0))
        self.done = True

    def _piece_end(self):
        return self.route.corners[self._piece + 1]

    def _locate(self, x, y):
        """Along-route distance of the robot's projection on the current piece,
        walking forward from the last segment (progress only moves forward). A
        robot nearer its last pursuit target than that projection cut across a
        curl of the piece: it is on the nearest segment up to the target's."""
        route, last = self.route, self._piece_end() - 1
        segment = max(self._segment, self.route.corners[self._piece])
        while True:
            t, gap = _project(route, segment, x, y)
            if t >= 1.0 and segment < last:
                segment += 1
                continue
            break
        if self._target is not None and distance(x, y, self._target[0], self._target[1]) ** 2 < gap:
            for later in range(segment + 1, min(self._target[2], last) + 1):
                t_later, gap_later = _project(route, later, x, y)
                if gap_later < gap:
                    segment, t, gap = later, t_later, gap_later
        self._segment = segment
        t = max(0.0, min(1.0, t))
        return route.s[segment] + t * (route.s[segment + 1] - route.s[segment])

    def _drive(self, odom):
        route = self.route
        along = self._locate(odom.x, odom.y)
        end_vertex = self._piece_end()
        remaining = route.s[end_vertex] - along
        if remaining <= max(odom.v, 0.0) * self.stop_lead:
            self._advance((route.s[end_vertex], 0.0))
            if end_vertex >= route.vertices - 1:
                self._finish()
                return (0.0, 0.0), None
            self.mode, self._stop_since = STOPPING, odom.stamp
            return (0.0, 0.0), None
        self._advance((along, 0.0))
        limit = self._limit()
        slowest = min(self.min_v, limit.max_v)
        speed = max(slowest, min(route.speed_at(along, self._segment), limit.max_v,
                                 math.sqrt(2.0 * self.brake_decel * remaining)))
        reach_ahead = max(self.lookahead, self.lookahead_time * speed)
        self._target = route.point_at(min(along + reach_ahead, route.s[end_vertex]), self._segment)
        tx, ty, _ = self._target
        reach = distance(odom.x, odom.y, tx, ty)
        alpha = wrap_angle(math.atan2(ty - odom.y, tx - odom.x) - odom.yaw)
        if abs(alpha) > math.pi / 3.0:
            # Target well off the bow (after a poor turn, or pushed off): face it first.
            return (0.0, math.copysign(min(limit.max_w, 2.0 * abs(alpha)), alpha)), abs(alpha)
        return (speed, 2.0 * speed * math.sin(alpha) / max(reach, 1e-6)), None

    def _stop(self, odom):
        still = abs(odom.v) <= self.stopped_v and abs(odom.w) <= self.stopped_w
        if still or odom.stamp - self._stop_since >= self.stop_timeout:
            self._piece += 1
            self._segment = self.route.corners[self._piece]
            self._target = None
            self._start_turn(odom)
        return 0.0, 0.0

    def _aim_heading(self, odom):
        """Heading from the robot to the route point ``aim_distance`` into the piece."""
        route = self.route
        corner = route.corners[self._piece]
        end = route.s[self._piece_end()]
        tx, ty, _ = route.point_at(min(route.s[corner] + self.aim_distance, end), corner)
        if distance(odom.x, odom.y, tx, ty) < 0.5 * self.aim_distance:
            return route.direction(corner)
        return math.atan2(ty - odom.y, tx - odom.x)

    def _start_turn(self, odom):
        angle = wrap_angle(self._aim_heading(odom) - odom.yaw)
        self.watch.new_heading_goal()
        corner = self.route.s[self.route.corners[self._piece]]
        if abs(angle) <= self.align_tolerance:
            self._advance((corner, 1.0))
            self.mode, self._rotation = DRIVING, None
            return
        limit = self._limit()
        turn = dict((name, _rotation_param(self.params, name)) for name in ROTATION_DEFAULTS)
        turn.update(angle=angle, max_w=limit.max_w, min_w=min(turn['min_w'], limit.max_w),
                    time_allowance=float('inf'))
        self._rotation = Rotation(SimpleNamespace(**turn))
        self._rotation.start(odom)
        self._turn_angle = angle
        self.mode = TURNING

    def _turn(self, odom):
        rotation = self._rotation
        command = rotation.step(odom)
        corner = self.route.s[self.route.corners[self._piece]]
        share = 1.0 - min(1.0, abs(rotation.remaining) / abs(self._turn_angle))
        self._advance((corner, 1.0 if rotation.done else share))
        if rotation.done:
            self.mode, self._rotation = DRIVING, None
        return command, abs(rotation.remaining)


def _project(route, segment, x, y):
    """(t, squared distance): the share along ``segment`` of the route of the
    projection of (x, y) (unclamped; 1 on a zero-length segment) and the squared
    distance from (x, y) to the segment."""
    ax, ay = route.x[segment], route.y[segment]
    dx, dy = route.x[segment + 1] - ax, route.y[segment + 1] - ay
    length_sq = dx * dx + dy * dy
    t = ((x - ax) * dx + (y - ay) * dy) / length_sq if length_sq > 0 else 1.0
    share = max(0.0, min(1.0, t))
    return t, (ax + share * dx - x) ** 2 + (ay + share * dy - y) ** 2


def _rotation_param(params, name):
    return float(getattr(params, name, ROTATION_DEFAULTS[name]) if params is not None
                 else ROTATION_DEFAULTS[name])

"""The closed-loop return: :class:`RouteFollower` drives the whole route back to the start,
pure pursuit between corners, a turn in place at each (docs/back_travel.md, "The route follower")."""
import math

from . import outcome
from .allowance import ProgressWatch
from .back_travel import BACK_TRAVEL_DEFAULTS, Odometer, _param
from .geometry import distance, wrap_angle
from .landmark import Landmark
from .rotation import ROTATION_DEFAULTS, Rotation
from .safety import VelocityLimits, goal_limits

DRIVING, STOPPING, TURNING, FINISHED = 'driving', 'stopping', 'turning', 'finished'


def section_limits(section, max_v, max_w, correction_w, creep_v):
    """core/safety.goal_limits of a route section; a slower stretch may be driven at ``creep_v``."""
    limits = goal_limits(Landmark(section.speed, section.turn_rate, 0.0, 1.0, 0.0),
                         max_v, max_w, correction_w)
    return limits._replace(max_v=max(limits.max_v, min(creep_v, max_v)))


class RouteFollower(Odometer):
    """Drives a core/route.Route: ``driving`` a piece, ``stopping`` and ``turning`` at a corner."""

    def __init__(self, route, params=None):
        self.route = route
        self.params = params
        for name in ('max_v', 'max_w', 'lookahead', 'min_v', 'stop_lead', 'lookahead_time',
                     'brake_decel', 'stopped_v', 'stopped_w', 'stop_timeout', 'align_tolerance',
                     'aim_distance', 'correction_w', 'timeout_factor', 'timeout_margin', 'creep_v',
                     'route_max_offset', 'finish_tolerance'):
            setattr(self, name, _param(params, name))
        self.limits = [section_limits(sec, self.max_v, self.max_w, self.correction_w, self.creep_v)
                       for sec in route.sections]
        self.nominal = [sec.nominal_time + abs(sec.turn) / max(limit.max_w, 1e-3)
                        for sec, limit in zip(route.sections, self.limits)]
        self.watch = ProgressWatch(sum(self.nominal), params)
        self.done = self.failed = False
        self.reason, self.code = '', outcome.NONE   # why it failed, core/outcome's cause
        self.mode, self.section, self.late, self.travelled = None, 0, [], 0.0
        self._mark = (0.0, 0.0)       # progress: (s along the route, phase of the corner turn)
        self._piece = self._segment = 0
        self._target = None           # the last pursuit target: (x, y, segment) on the current piece
        self._rotation = self._last = self._stop_since = None
        self._turn_angle = self._section_started = 0.0

    started = property(lambda self: self._last is not None)
    progress = property(lambda self: self._mark)   # (m along the route, phase of its corner's turn)

    def section_finished(self, index):
        return self.done or self._mark >= self.route.section_end(index)

    def _advance(self, mark):
        """Move the progress mark forward (never back); close finished sections."""
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

    def start(self, odom_state, section=0):
        """Start (or resume at goal ``section``) from ``odom_state``."""
        route = self.route
        if not 0 <= section <= len(route.sections):
            raise ValueError('cannot start at section %d of %d' % (section, len(route.sections)))
        self._last, self.travelled, self.reason = odom_state, 0.0, ''
        self.done = self.failed = False
        self.watch.update(odom_state.stamp, 0.0)
        mark = (0.0, 0.0) if section == 0 else route.section_end(section - 1)
        vertex = 0 if section == 0 else route.sections[section - 1].end_vertex
        self._mark, self.section, self._section_started = mark, section, self.watch.active
        self._advance(mark)
        if route.vertices == 1 or vertex >= route.vertices - 1:
            self._finish(odom_state)
            return
        self._piece, self._segment, self._target = route.piece_of(vertex), vertex, None
        if route.corner[vertex] and mark[1] < 1.0:
            self._start_turn(odom_state)
        else:
            self.mode = DRIVING

    def step(self, odom_state):
        """(v, w) for this control cycle; sets done / failed (then (0, 0))."""
        if self._last is None:
            raise RuntimeError('RouteFollower.step called before start')
        if self._count_step(odom_state):
            return 0.0, 0.0
        if self.mode == DRIVING:
            command, heading_error = self._drive(odom_state)
        elif self.mode == STOPPING:
            command, heading_error = self._stop(odom_state), None
        else:
            command, heading_error = self._turn(odom_state)
        why = self.watch.update(odom_state.stamp, self._mark[0], heading_error)
        if why and not self.done and not self.failed:
            self._fail(outcome.TIMEOUT, why)
        if self.done or self.failed:
            return 0.0, 0.0
        return self._limit().clamp(*command)

    def _finish(self, odom):
        """The route's end reached: finished if the robot stops within ``finish_tolerance``."""
        off = self.off_end(odom)
        if off > self.finish_tolerance:
            self._fail(outcome.NOT_HOME, 'the route ends %.2f m from where the robot stops (finish_tolerance %.2f m)'
                       % (off, self.finish_tolerance))
            return
        self.mode = FINISHED
        self._advance((self.route.length, 1.0))
        self.done = True

    def off_end(self, odom):
        """m from where the robot stops (coasting ``stop_lead`` s) to the route's end."""
        coast = max(odom.v, 0.0) * self.stop_lead
        return distance(odom.x + coast * math.cos(odom.yaw), odom.y + coast * math.sin(odom.yaw),
                        self.route.x[-1], self.route.y[-1])

    def _fail(self, code, reason):
        self.failed, self.reason, self.code = True, reason, code

    def _piece_end(self):
        return self.route.corners[self._piece + 1]

    def _locate(self, x, y):
        """(along-route distance, offset) of the robot's projection on the current piece, walking
        forward; nearer the last target than that, it cut a curl: the nearest segment up to it."""
        route, last = self.route, self._piece_end() - 1
        segment = max(self._segment, self.route.corners[self._piece])
        t, gap = _project(route, segment, x, y)
        while t >= 1.0 and segment < last:
            segment += 1
            t, gap = _project(route, segment, x, y)
        if self._target is not None and distance(x, y, self._target[0], self._target[1]) ** 2 < gap:
            for later in range(segment + 1, min(self._target[2], last) + 1):
                t_later, gap_later = _project(route, later, x, y)
                if gap_later < gap:
                    segment, t, gap = later, t_later, gap_later
        self._segment = segment
        t = max(0.0, min(1.0, t))
        return route.s[segment] + t * (route.s[segment + 1] - route.s[segment]), math.sqrt(gap)

    def _drive(self, odom):
        route = self.route
        along, off = self._locate(odom.x, odom.y)
        if off > self.route_max_offset:
            self._fail(outcome.OFF_ROUTE, 'the robot is %.2f m off the route at %.2f m along it (route_max_offset '
                       '%.2f m): not rejoining it' % (off, along, self.route_max_offset))
            return (0.0, 0.0), None
        end_vertex = self._piece_end()
        remaining = route.s[end_vertex] - along
        coast = max(odom.v, 0.0) * self.stop_lead
        if remaining <= coast:
            if end_vertex >= route.vertices - 1:
                self._finish(odom)
                return (0.0, 0.0), None
            self._advance((route.s[end_vertex], 0.0))
            self.mode, self._stop_since = STOPPING, odom.stamp
            return (0.0, 0.0), None
        self._advance((along, 0.0))
        limit = self._limit()
        slowest = min(self.min_v, limit.max_v)
        speed = max(slowest, min(route.speed_at(along, self._segment), limit.max_v,
                                 math.sqrt(2.0 * self.brake_decel * max(remaining - coast, 0.0))))
        reach_ahead = max(self.lookahead, self.lookahead_time * speed)
        self._target = route.point_at(min(along + reach_ahead, route.s[end_vertex]), self._segment)
        tx, ty, _ = self._target
        reach = distance(odom.x, odom.y, tx, ty)
        alpha = wrap_angle(math.atan2(ty - odom.y, tx - odom.x) - odom.yaw)
        if abs(alpha) > math.pi / 3.0:
            return (0.0, math.copysign(min(limit.max_w, 2.0 * abs(alpha)), alpha)), abs(alpha)
        return (speed, 2.0 * speed * math.sin(alpha) / max(reach, 1e-6)), None

    def _stop(self, odom):
        still = abs(odom.v) <= self.stopped_v and abs(odom.w) <= self.stopped_w
        if still or odom.stamp - self._stop_since >= self.stop_timeout:
            self._piece += 1
            self._segment, self._target = self.route.corners[self._piece], None
            self._start_turn(odom)
        return 0.0, 0.0

    def _start_turn(self, odom):
        """Face the route point ``aim_distance`` ahead of the corner (its direction, that near)."""
        route, corner = self.route, self.route.corners[self._piece]
        tx, ty, _ = route.point_at(min(route.s[corner] + self.aim_distance,
                                       route.s[self._piece_end()]), corner)
        near = distance(odom.x, odom.y, tx, ty) < 0.5 * self.aim_distance
        aim = route.direction(corner) if near else math.atan2(ty - odom.y, tx - odom.x)
        angle = wrap_angle(aim - odom.yaw)
        self.watch.new_heading_goal()
        if abs(angle) <= self.align_tolerance:
            self._advance((route.s[corner], 1.0))
            self.mode, self._rotation = DRIVING, None
            return
        max_w = self._limit().max_w
        self._rotation = Rotation(self.params, angle=angle, max_w=max_w, time_allowance=math.inf,
                                  min_w=min(_param(self.params, 'min_w', ROTATION_DEFAULTS), max_w))
        self._rotation.start(odom)
        self._turn_angle, self.mode = angle, TURNING

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
    """(t, squared distance): unclamped share of (x, y)'s projection on ``segment``, its gap."""
    ax, ay = route.x[segment], route.y[segment]
    dx, dy = route.x[segment + 1] - ax, route.y[segment + 1] - ay
    length_sq = dx * dx + dy * dy
    t = ((x - ax) * dx + (y - ay) * dy) / length_sq if length_sq > 0 else 1.0
    share = max(0.0, min(1.0, t))
    return t, (ax + share * dx - x) ** 2 + (ay + share * dy - y) ** 2

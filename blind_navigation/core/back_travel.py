"""Back-travel controllers: drive one path landmark of the return (paper 3.3.5).

After the pi turn the robot drives *forward* along the recorded path in the
opposite direction, landmarks in reverse order. Reversing time on a path
traversed with ``(v, w)`` while the robot faces the other way gives the command
``(v, -w)``: the linear velocity is replayed as recorded and the turn rate is
mirrored (a left arc going out is a right arc coming back).

Modes (``make_controller(mode, landmark, params, route)``):

- ``time`` -- the paper's sampled-time control: publish the landmark's velocity
  for its period ``T``. Straight segments (``T`` equal to the straight, longer
  period) publish the linear velocity only, curved ones linear and angular.
- ``distance`` -- the paper's travelled-distance control: the same velocities
  until odometry shows the landmark's ``d`` covered.
- ``closed_loop`` -- this package's mode (the paper's limitation 4, "does not
  correct drift"): the landmarks' ``(d, psi)`` chain rebuilds the recorded path
  in the odometry frame (:class:`ReturnRoute`), anchored where recording
  stopped; pure pursuit tracks it backwards, correcting heading and
  cross-track drift; each goal ends when the along-track progress reaches the
  landmark's end point, less the distance the robot coasts after its last
  command (``stop_lead`` x measured speed: the server's handover timeout plus
  the base's velocity time constant), so the last goal stops on the start.
  Speed is the recorded one (at least ``min_v``).

Each controller: ``start(odom_state)``, ``step(odom_state) -> (v, w)`` until
``done`` (or ``failed``: the goal's time allowance ran out), ``travelled`` =
odometry path length since start. Times come from ``odom_state.stamp``. Every
command is clamped to ``max_v``/``max_w``.
"""
import math

from .geometry import distance, wrap_angle

MODES = ('time', 'distance', 'closed_loop')

#: Defaults; the back_travel_server node exposes each one as a ~private param.
BACK_TRAVEL_DEFAULTS = {
    'straight_period': 2.0,   # s; a landmark with T >= this is a straight segment
    'max_v': 0.5,             # m/s, hard clamp on |v|
    'max_w': 1.0,             # rad/s, hard clamp on |w|
    'timeout_factor': 3.0,    # allowance = factor * expected duration + margin
    'timeout_margin': 2.0,    # s
    'lookahead': 0.1,         # m, pure-pursuit lookahead (closed_loop)
    'min_v': 0.03,            # m/s, slowest closed-loop speed
    'min_d': 0.002,           # m, goals shorter than this end at once (distance, closed_loop)
    'stop_lead': 0.2,         # s the robot coasts after its last command (closed_loop)
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


class ReturnRoute(object):
    """The recorded path rebuilt from landmarks, as waypoints in return order.

    ``points[0]`` is the anchor (odometry position where recording stopped,
    i.e. the last landmark's position). Each :meth:`add` (landmarks arrive in
    reverse order) appends the previous landmark's position ``d`` back along
    the chord. A chord between two landmarks has heading
    ``(psi_prev + psi_next) / 2`` (exact on an arc of constant curvature); the
    newest chord's far end is not known yet, so it is provisional
    (heading ``psi - w T / 2``) and is corrected when the next
    landmark arrives. Errors of provisional ends therefore do not accumulate.
    """

    def __init__(self, anchor=None, straight_period=BACK_TRAVEL_DEFAULTS['straight_period']):
        self.points = [tuple(anchor)] if anchor is not None else []
        self.straight_period = straight_period
        self._last_landmark = None
        self._segment = 0      # index of the segment the robot was last closest to

    @property
    def anchored(self):
        return bool(self.points)

    def anchor_at(self, x, y):
        if self.points:
            raise RuntimeError('route already anchored')
        self.points.append((x, y))

    def add(self, landmark):
        """Extend the route by one landmark (reverse recording order)."""
        if not self.points:
            raise RuntimeError('route has no anchor')
        previous = self._last_landmark
        if previous is not None:
            heading = previous.psi + wrap_angle(landmark.psi - previous.psi) / 2.0
            self.points[-1] = self._back(self.points[-2], previous.d, heading)
        heading = landmark.psi - landmark.w * landmark.T / 2.0
        self.points.append(self._back(self.points[-1], landmark.d, heading))
        self._last_landmark = landmark

    @staticmethod
    def _back(point, length, heading):
        return (point[0] - length * math.cos(heading), point[1] - length * math.sin(heading))

    def length_to(self, index):
        """Route length from the anchor to ``points[index]``."""
        return sum(distance(a[0], a[1], b[0], b[1])
                   for a, b in zip(self.points[:index], self.points[1:index + 1]))

    def locate(self, x, y):
        """Along-route distance of the point of the route closest to (x, y),
        searched near the last segment found (progress only moves locally).
        Zero-length segments (landmarks recorded standing still) do not count
        towards that window, so a pause cannot hide the route beyond it."""
        best = None
        last = len(self.points) - 2
        i, end = max(0, self._segment - 1), min(last, self._segment + 3)
        while i <= end:
            (ax, ay), (bx, by) = self.points[i], self.points[i + 1]
            length_sq = (bx - ax) ** 2 + (by - ay) ** 2
            if length_sq < 1e-12:
                end = min(last, end + 1)
            t = 0.0 if length_sq < 1e-12 else ((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / length_sq
            t = max(0.0, min(1.0, t)) if i < last else max(0.0, t)
            gap = distance(x, y, ax + t * (bx - ax), ay + t * (by - ay))
            if best is None or gap < best[0] - 1e-9:
                best = (gap, i, t)
            i += 1
        _, self._segment, t = best
        seg_length = distance(*(self.points[self._segment] + self.points[self._segment + 1]))
        return self.length_to(self._segment) + t * seg_length

    def point_at(self, s):
        """Point at along-route distance ``s``; beyond the end, straight on."""
        travelled, last = 0.0, len(self.points) - 2
        for i, ((ax, ay), (bx, by)) in enumerate(zip(self.points, self.points[1:])):
            length = distance(ax, ay, bx, by)
            if length > 1e-9 and (s <= travelled + length or i == last):
                t = (s - travelled) / length
                return ax + t * (bx - ax), ay + t * (by - ay)
            travelled += length
        return self.points[-1]


class PursuitController(_Controller):
    """Closed-loop mode: pure pursuit along a :class:`ReturnRoute`."""

    def __init__(self, landmark, params, route=None):
        self.min_v = _param(params, 'min_v')
        super(PursuitController, self).__init__(landmark, params)
        self.lookahead = _param(params, 'lookahead')
        self.min_d = _param(params, 'min_d')
        self.stop_lead = _param(params, 'stop_lead')
        self.route = route if route is not None else ReturnRoute(
            straight_period=self.straight_period)
        self.speed = min(max(abs(landmark.v), self.min_v), self.max_v)
        self.goal_end = None

    def expected_duration(self, params):
        return max(self.landmark.T, self.landmark.d / max(abs(self.landmark.v), self.min_v))

    def start(self, odom_state):
        super(PursuitController, self).start(odom_state)
        if not self.route.anchored:
            self.route.anchor_at(odom_state.x, odom_state.y)
        self.route.add(self.landmark)
        self.goal_end = self.route.length_to(len(self.route.points) - 1)
        if self.landmark.d < self.min_d:
            self.done = True

    def command(self, odom_state):
        progress = self.route.locate(odom_state.x, odom_state.y)
        if progress + max(odom_state.v, 0.0) * self.stop_lead >= self.goal_end:
            self.done = True
            return 0.0, 0.0
        tx, ty = self.route.point_at(progress + self.lookahead)
        reach = distance(odom_state.x, odom_state.y, tx, ty)
        alpha = wrap_angle(math.atan2(ty - odom_state.y, tx - odom_state.x) - odom_state.yaw)
        if abs(alpha) > math.pi / 3.0:
            # Target well off the bow (e.g. after a poor turn): rotate towards it first.
            return 0.0, math.copysign(min(self.max_w, 2.0 * abs(alpha)), alpha)
        return self.speed, 2.0 * self.speed * math.sin(alpha) / max(reach, 1e-6)


def make_controller(mode, landmark, params=None, route=None):
    """Controller for one landmark; ``route`` (closed_loop only) is shared by the
    goals of one return so the path is tracked as a whole."""
    if mode == 'time':
        return TimeController(landmark, params)
    if mode == 'distance':
        return DistanceController(landmark, params)
    if mode == 'closed_loop':
        return PursuitController(landmark, params, route)
    raise ValueError('unknown back-travel mode %r (expected one of %s)' % (mode, ', '.join(MODES)))

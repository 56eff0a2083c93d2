"""A human teleoperator watching the robot: keeps it on the mission's path by keyboard.

:class:`Operator` (for the mission driver node and the harness): TurtleBot's keyboard
teleop (forward at LSV, turns at +-ASV), the true pose seen ``reaction_time`` late,
two-point steering toward a point ``preview`` ahead, intermittent taps once the error
exceeds ``press_threshold``, a ``refractory`` wait; forward only. Parameters and their
human-factors sources: :data:`OPERATOR_DEFAULTS` (docs/fake_turtlebot.md).
"""
import bisect
import math
from collections import deque

from ..core.geometry import wrap_angle

#: Operator parameters (see module docstring); ``max_w`` None = the mission's largest |w|.
OPERATOR_DEFAULTS = {
    'reaction_time': 0.3,       # s, the pose the person reacts to is this old
    'preview': 1.0,             # m, aim point ahead on the route
    'max_w': None,              # rad/s, the turn key's rate (ASV)
    'press_threshold': 0.04,    # rad, smallest heading error the person corrects (~2.3 deg)
    'refractory': 0.5,          # s after a tap before the next judgement
    'allowance_factor': 3.0,    # the mission is abandoned after factor x nominal duration
}
RESOLUTION = 0.01               # m between route points


def operator_params(values, where='operator'):
    """Validated operator parameters: defaults with ``values`` (a mapping) on top."""
    if not isinstance(values, dict):
        raise ValueError('%s: operator parameters are a mapping, got %r' % (where, values))
    unknown = set(values) - set(OPERATOR_DEFAULTS)
    if unknown:
        raise ValueError('%s: unknown operator parameter(s) %s' % (where, sorted(unknown)))
    params = dict(OPERATOR_DEFAULTS, **values)
    for key, value in params.items():
        if value is None and key == 'max_w':
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
            raise ValueError('%s: %s must be a number >= 0, got %r' % (where, key, value))
    return params


class ReferencePath(object):
    """The moving segments ``(v, w, duration)`` laid end to end from ``start``
    ``(x, y, yaw)``: points every RESOLUTION m with along-route distance ``s``."""

    def __init__(self, segments, start=(0.0, 0.0, 0.0)):
        x, y, yaw = start
        self.s, self.x, self.y, self.yaw = [0.0], [x], [y], [yaw]
        for v, w, duration in segments:
            length = abs(v) * duration
            if length <= 0.0:
                continue
            curvature = w / abs(v)
            steps = max(1, int(math.ceil(length / RESOLUTION)))
            ds = length / steps
            for _ in range(steps):
                mid = yaw + curvature * ds / 2.0
                x, y, yaw = x + ds * math.cos(mid), y + ds * math.sin(mid), yaw + curvature * ds
                self.s.append(self.s[-1] + ds)
                self.x.append(x)
                self.y.append(y)
                self.yaw.append(yaw)
        self.length = self.s[-1]
        self._index = 0

    def point_at(self, s):
        """(x, y) at along-route distance ``s``; beyond the end, straight on."""
        if s >= self.length:
            extra = s - self.length
            return (self.x[-1] + extra * math.cos(self.yaw[-1]), self.y[-1] + extra * math.sin(self.yaw[-1]))
        i = min(max(bisect.bisect_right(self.s, s) - 1, 0), len(self.s) - 2)
        t = (s - self.s[i]) / max(self.s[i + 1] - self.s[i], 1e-12)
        return (self.x[i] + t * (self.x[i + 1] - self.x[i]), self.y[i] + t * (self.y[i + 1] - self.y[i]))

    def locate(self, x, y, window=0.5):
        """Along-route distance and signed lateral offset (m, left +) of the
        route point nearest (x, y), searched within ``window`` m of the last one."""
        span = int(window / RESOLUTION)
        lo, hi = max(0, self._index - span), min(len(self.s) - 1, self._index + 2 * span)
        best = min(range(lo, hi + 1), key=lambda i: (self.x[i] - x) ** 2 + (self.y[i] - y) ** 2)
        self._index = best
        dx, dy = x - self.x[best], y - self.y[best]
        heading = self.yaw[best]
        along = dx * math.cos(heading) + dy * math.sin(heading)
        lateral = -dx * math.sin(heading) + dy * math.cos(heading)
        return self.s[best] + (along if best in (0, len(self.s) - 1) else 0.0), lateral


class Operator(object):
    """One person driving one mission; see the module docstring.

    ``start(pose)`` at mission time 0 (anchors the route at the true start pose),
    ``observe(t, pose)`` for every true pose seen (mission time ``t``, any rate),
    ``command(t)`` -> ``(v, w)`` at the teleop rate, None once the route is done.
    """

    def __init__(self, mission, params=None):
        self.mission = mission
        self.params = p = operator_params(params or {}, mission.name)
        reversing = [i for i, segment in enumerate(mission.segments) if segment[0] < 0]
        if reversing:
            raise ValueError('%s: segments %s reverse (v < 0): the operator steers forward only; '
                             'play a reversing mission as the open-loop script (no operator:)'
                             % (mission.name, reversing))
        self.max_w = p['max_w'] if p['max_w'] is not None else max(abs(s[1]) for s in mission.segments)
        if not self.max_w > 0:
            raise ValueError('%s: the operator needs a turn rate (max_w or a segment with w)' % mission.name)
        self.period = 1.0 / mission.rate
        self.allowance = p['allowance_factor'] * mission.duration
        self._seen = deque()
        self._route = None
        self._piece = 0
        self._piece_started = 0.0
        self._tap = (0.0, 0.0, 0.0)
        self.lateral = 0.0          # m, last perceived offset from the route (left +)
        self.progress = 0.0         # m along the route

    @property
    def started(self):
        return self._route is not None

    def start(self, pose):
        """The mission starts now (t = 0) with the robot at ``pose`` (Pose2D, true)."""
        self._route = ReferencePath(self.mission.segments, (pose.x, pose.y, pose.yaw))
        self._seen.clear()
        self._seen.append((0.0, pose))
        self._piece, self._piece_started = 0, 0.0
        self._tap = (0.0, 0.0, 0.0)     # (turn rate, until, no judgement until)
        self._piece_ends = []
        s = 0.0
        for v, _, duration in self.mission.segments:
            s += abs(v) * duration
            self._piece_ends.append(s)

    def observe(self, t, pose):
        """The true pose at mission time ``t`` (what the person sees, later)."""
        if self._route is None:
            raise RuntimeError('Operator.observe before start')
        self._seen.append((t, pose))
        while len(self._seen) > 1 and self._seen[1][0] <= t - self.params['reaction_time']:
            self._seen.popleft()

    def _perceived(self, t):
        """The newest pose at least reaction_time old (the oldest kept otherwise)."""
        return self._seen[0][1]

    def command(self, t):
        """(v, w) the person sends at mission time ``t``; None once done or past the allowance."""
        if self._route is None:
            raise RuntimeError('Operator.command before start')
        if t > self.allowance or self._piece >= len(self.mission.segments):
            return None
        pose = self._perceived(t)
        self.progress, self.lateral = self._route.locate(pose.x, pose.y)
        v, w, duration = self.mission.segments[self._piece]
        if v == 0.0:                       # pause or turn on the spot: by the clock
            if t - self._piece_started >= duration:
                return self._next_piece(t)
            return v, w
        if self.progress >= self._piece_ends[self._piece] - 1e-9:
            return self._next_piece(t)
        aim = self._route.point_at(self.progress + self.params['preview'])
        error = wrap_angle(math.atan2(aim[1] - pose.y, aim[0] - pose.x) - pose.yaw)
        return v, self._keys(t, error)

    def _next_piece(self, t):
        self._piece += 1
        self._piece_started = t
        return self.command(t)

    def _keys(self, t, error):
        """Turn key for this teleop period: a tap in progress, or a new one."""
        rate, until, quiet_until = self._tap
        if t < until - 1e-9:
            return rate
        if t >= quiet_until - 1e-9 and abs(error) >= self.params['press_threshold']:
            periods = max(1, int(round(abs(error) / self.max_w / self.period)))
            until = t + periods * self.period
            self._tap = (math.copysign(self.max_w, error), until, until + self.params['refractory'])
            return self._tap[0]
        return 0.0

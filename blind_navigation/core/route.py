"""The whole return route, built at once from the recorded landmarks (closed-loop return):
``build_route(landmarks, anchor)`` -> :class:`Route` (docs/back_travel.md, "The route")."""
import bisect
import math
from collections import namedtuple
from itertools import accumulate

from .geometry import wrap_angle
from .period_model import period_shape, period_turn
from .plausibility import nonnegative_param
from .safety import SAFETY_DEFAULTS, expected_duration, recorded_speed

#: Defaults of the route building.
ROUTE_DEFAULTS = {
    'merge_distance': 0.01,   # m; route points closer than this merge into one
    'in_place_radius': 0.1,   # m; a period that turned on a smaller radius is a turn in place
    'corner_angle': 0.5,      # rad; a turn at one point larger than this is a corner (stop, turn in place)
    'curve_step': 0.1,        # rad; largest heading change between modelled points within a period
    'curve_spacing': 0.1,     # m; largest distance between modelled points within a period
    'slowest_v': SAFETY_DEFAULTS['slowest_v'],  # m/s assumed for slower landmarks, when timing one
}
#: Most modelled points within one period.
MAX_SUBDIVISIONS = 32
#: A turn in place moves the base by wheel jitter only: at most this many merge distances.
IN_PLACE_JITTER = 3.0

SECTION_FIELDS = ('end_vertex', 'end_phase', 'speed', 'turn_rate', 'nominal_time', 'turn')
ROUTE_FIELDS = ('x', 'y', 'speed', 'corner') + tuple('section_' + f for f in SECTION_FIELDS)


def _param(params, name):
    return nonnegative_param(params, name, ROUTE_DEFAULTS, 'route')


def route_lists(route):
    """{field: [float, ...]} (:data:`ROUTE_FIELDS`) of a Route or a ReturnRoute message."""
    data = {'x': list(route.x), 'y': list(route.y), 'speed': list(route.speed),
            'corner': [1.0 if c else 0.0 for c in route.corner]}
    for field in SECTION_FIELDS:
        data['section_' + field] = [float(getattr(s, field)) for s in route.sections]
    return data


class Section(namedtuple('Section', SECTION_FIELDS)):
    """One goal of the return (one landmark): its end mark, recorded rates, nominal time, turn."""

    __slots__ = ()


class Route(object):
    """Vertices ``x``, ``y`` (return order: 0 the anchor), their ``speed`` and ``corner``
    flags, cumulative length ``s`` and the :class:`Section` list."""

    def __init__(self, x, y, speed, corner, sections):
        if not (len(x) == len(y) == len(speed) == len(corner)) or not x:
            raise ValueError('route: x, y, speed and corner must have the same, non-zero length '
                             '(%d, %d, %d, %d)' % (len(x), len(y), len(speed), len(corner)))
        self.x, self.y = [float(v) for v in x], [float(v) for v in y]
        self.speed = [float(v) for v in speed]
        self.corner = [bool(c) for c in corner]
        self.corner[0] = self.corner[-1] = True
        self.sections = list(sections)
        self.s = list(accumulate((math.hypot(self.x[i] - self.x[i - 1], self.y[i] - self.y[i - 1])
                                  for i in range(1, len(self.x))), initial=0.0))
        self.corners = [i for i, flag in enumerate(self.corner) if flag]
        previous = (0, 0.0)
        for index, section in enumerate(self.sections):
            mark = (section.end_vertex, section.end_phase)
            if not 0 <= section.end_vertex < len(self.x) or not 0.0 <= section.end_phase <= 1.0:
                raise ValueError('route: section %d ends at vertex %d phase %r, outside the route'
                                 % (index, section.end_vertex, section.end_phase))
            if mark < previous:
                raise ValueError('route: section %d ends before section %d' % (index, index - 1))
            previous = mark

    length = property(lambda self: self.s[-1])
    vertices = property(lambda self: len(self.x))

    def section_end(self, index):
        """``(s, phase)`` progress mark at which section ``index`` is finished."""
        section = self.sections[index]
        return self.s[section.end_vertex], section.end_phase

    def piece_of(self, vertex):
        """Index of the piece (between two corners) that starts at or contains ``vertex``."""
        return max(0, min(bisect.bisect_right(self.corners, vertex), len(self.corners) - 1) - 1)

    def direction(self, segment):
        """Heading (rad) of the segment from vertex ``segment`` to the next."""
        return math.atan2(self.y[segment + 1] - self.y[segment], self.x[segment + 1] - self.x[segment])

    def point_at(self, s, segment=0):
        """(x, y, segment) at along-route distance ``s`` (clamped), searching from ``segment``."""
        last = len(self.x) - 1
        if last == 0:
            return self.x[0], self.y[0], 0
        segment = max(0, min(segment, last - 1))
        while segment < last - 1 and self.s[segment + 1] < s:
            segment += 1
        while segment > 0 and self.s[segment] > s:
            segment -= 1
        t = self._share(s, segment)
        return (self.x[segment] + t * (self.x[segment + 1] - self.x[segment]),
                self.y[segment] + t * (self.y[segment + 1] - self.y[segment]), segment)

    def speed_at(self, s, segment):
        """Modelled recorded speed at along-route distance ``s`` on ``segment`` (m/s)."""
        if len(self.x) == 1:
            return self.speed[0]
        return self.speed[segment] + self._share(s, segment) * (self.speed[segment + 1] - self.speed[segment])

    def _share(self, s, segment):
        length = self.s[segment + 1] - self.s[segment]
        return 0.0 if length <= 0 else max(0.0, min(1.0, (s - self.s[segment]) / length))

    to_lists = route_lists

    @classmethod
    def from_lists(cls, data):
        """A Route from :meth:`to_lists`' form; ValueError naming the bad field."""
        if not isinstance(data, dict) or set(data) != set(ROUTE_FIELDS):
            raise ValueError('route data must have exactly the fields %s' % ', '.join(ROUTE_FIELDS))
        for name in ROUTE_FIELDS:
            values = data[name]
            if not isinstance(values, (list, tuple)) or not all(
                    isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                    for v in values):
                raise ValueError('route field %s must be a list of finite numbers' % name)
        lengths = {len(data['section_' + f]) for f in SECTION_FIELDS}
        if len(lengths) != 1:
            raise ValueError('route section fields differ in length: %s' % sorted(lengths))
        for value in data['section_end_vertex']:
            if value != int(value):
                raise ValueError('route field section_end_vertex must hold whole numbers, got %r' % value)
        sections = [Section(int(end), *values)
                    for end, *values in zip(*(data['section_' + f] for f in SECTION_FIELDS))]
        return cls(data['x'], data['y'], data['speed'], [v != 0.0 for v in data['corner']], sections)


def _subdivisions(a, b, d, params):
    turn = abs(period_turn(a, b))
    step, spacing = _param(params, 'curve_step'), _param(params, 'curve_spacing')
    count = max(turn / step if step > 0 else 1.0, d / spacing if spacing > 0 else 1.0)
    return int(min(MAX_SUBDIVISIONS, max(1, math.ceil(count - 1e-9))))


def _start_state(first):
    """The state at the start of the recording: the first landmark extrapolated back."""
    return first._replace(psi=wrap_angle(first.psi - first.w * first.T))


def build_route(landmarks, anchor, params=None):
    """The :class:`Route` back from ``anchor`` (x, y) through ``landmarks`` (recording order)."""
    try:
        ax, ay = (float(c) for c in anchor)
    except (TypeError, ValueError):
        raise ValueError('route anchor must be (x, y), got %r' % (anchor,))
    if not (math.isfinite(ax) and math.isfinite(ay)):
        raise ValueError('route anchor must be finite, got %r' % (anchor,))
    landmarks = list(landmarks)
    for index, landmark in enumerate(landmarks):
        if len(landmark) != 5 or not all(math.isfinite(v) for v in landmark) \
                or landmark.d < 0 or landmark.T <= 0:
            raise ValueError('landmark %d is not a valid landmark: %r' % (index + 1, landmark))
    return _assemble((ax, ay), landmarks, _chain((ax, ay), landmarks, params), params)


def _chain(anchor, landmarks, params):
    """Per landmark (return order): (its point, its period's modelled points and speeds,
    the previous landmark's point, the period's turn, turned in place) back from ``anchor``."""
    point = anchor
    chain = []
    for k in range(len(landmarks) - 1, -1, -1):
        b = landmarks[k]
        a = landmarks[k - 1] if k > 0 else _start_state(b)
        direction, offsets, speeds, turn = period_shape(a, b, b.d, _subdivisions(a, b, b.d, params))
        start = (point[0] - b.d * math.cos(direction), point[1] - b.d * math.sin(direction))
        inner = [(start[0] + ox, start[1] + oy) for ox, oy in offsets]
        in_place = b.d < min(_param(params, 'in_place_radius') * abs(turn),
                             IN_PLACE_JITTER * _param(params, 'merge_distance'))
        chain.append((point, [] if in_place else inner[::-1], speeds[::-1], start, turn, in_place))
        point = start
    return chain


def _assemble(anchor, landmarks, chain, params):
    """Merge close points, find corners, place the sections' ends."""
    merge = _param(params, 'merge_distance')
    xs, ys, speeds = [anchor[0]], [anchor[1]], [abs(landmarks[-1].v) if landmarks else 0.0]
    end_vertex = []        # per section (return order): the kept vertex where it ends
    start_vertex = []

    def add(p, speed, in_place=False):
        gap = math.hypot(p[0] - xs[-1], p[1] - ys[-1])
        if gap >= (IN_PLACE_JITTER * merge if in_place else merge):
            xs.append(p[0])
            ys.append(p[1])
            speeds.append(speed)
        else:
            speeds[-1] = max(speeds[-1], speed)

    for point, inner, inner_speeds, start, _, in_place in chain:
        start_vertex.append(len(xs) - 1)
        # inner_speeds: [end speed, intermediate speeds..., start speed] in return order
        for p, speed in zip(inner, inner_speeds[1:-1] if len(inner_speeds) > 2 else []):
            add(p, speed)
        add(start, 0.0 if in_place else inner_speeds[-1], in_place)
        end_vertex.append(len(xs) - 1)
    if chain:   # the start of the recording is the goal: the last vertex exactly on it
        final = chain[-1][3]
        if len(xs) > 1:
            xs[-1], ys[-1] = final
        elif math.hypot(final[0] - xs[0], final[1] - ys[0]) > 1e-9:
            xs.append(final[0])
            ys.append(final[1])
            speeds.append(speeds[0])
        # the last landmarks, recorded standing where the recording started, end on it (only
        # the trailing run: an earlier return to that exact point is not the route's end)
        for index in range(len(chain) - 1, -1, -1):
            if chain[index][3] != final:
                break
            end_vertex[index] = len(xs) - 1
    corner_angle = _param(params, 'corner_angle')
    corner = [abs(corner_turn(xs, ys, i)) > corner_angle for i in range(len(xs))]
    corner[0] = corner[-1] = True
    sections = _sections(landmarks, chain, start_vertex, end_vertex, xs, ys, corner, params)
    return Route(xs, ys, speeds, corner, sections)


def corner_turn(xs, ys, vertex):
    """Turn (rad) the route makes at ``vertex`` (0 at the ends)."""
    if vertex <= 0 or vertex >= len(xs) - 1:
        return 0.0
    before = math.atan2(ys[vertex] - ys[vertex - 1], xs[vertex] - xs[vertex - 1])
    after = math.atan2(ys[vertex + 1] - ys[vertex], xs[vertex + 1] - xs[vertex])
    return wrap_angle(after - before)


def _sections(landmarks, chain, start_vertex, end_vertex, xs, ys, corner, params):
    """Sections in return order (a turn in place at a corner ends with its share of the turn)."""
    slowest_v = _param(params, 'slowest_v')
    n = len(landmarks)
    phases = [0.0] * n
    owned = [0.0] * n
    initial = 0.0
    if n and len(xs) > 1:   # after the pi turn the robot faces the last heading + pi
        initial = wrap_angle(math.atan2(ys[1] - ys[0], xs[1] - xs[0]) - landmarks[-1].psi - math.pi)
    first = 0          # first section not ending before the corner looked at
    for vertex in (v for v, flag in enumerate(corner[:-1]) if flag):
        while first < n and end_vertex[first] < vertex:
            first += 1
        standing = first      # a drive section arriving here ends on arrival
        while standing < n and end_vertex[standing] == vertex and start_vertex[standing] < vertex:
            standing += 1
        leaving = standing    # those standing here (recorded turning in place) share the turn
        while leaving < n and start_vertex[leaving] == end_vertex[leaving] == vertex:
            leaving += 1
        angle = abs(initial if vertex == 0 else corner_turn(xs, ys, vertex))
        group = list(range(standing, leaving))
        turns = [abs(chain[k][4]) for k in group]
        total = sum(turns)
        if group and total > 0 and total >= 0.25 * angle:
            done = 0.0
            for k, turn in zip(group, turns):
                done += turn
                phases[k] = min(1.0, done / total)
                owned[k] = angle * turn / total
            phases[group[-1]] = 1.0
        elif leaving < n:
            owned[leaving] += angle
    sections = []
    for i in range(n):
        landmark = landmarks[n - 1 - i]
        turn = chain[i][4]
        sections.append(Section(end_vertex[i], phases[i], recorded_speed(landmark),
                                max(abs(landmark.w), abs(turn) / landmark.T),
                                expected_duration(landmark, slowest_v), owned[i]))
    return sections

"""The odometry drift over a loop of the recorded path: how far apart two passes may
truly be where odometry puts them together (core/pruning.py cuts only within its radius).

Four independent parts (gyro bias and scale left after the correction, gyro white noise,
wheel error per metre); :meth:`Drift.plus` adds skipped loops; O(1) per loop after an
O(n) pass (docs/pruning.md, "Honest about drift").
"""
import math
from collections import namedtuple

from .period_model import period_turn

#: Error model of the odometry over a loop (the back-travel client exposes them as ~params).
#: wheel_error_per_m: the paper profile's encoder distance error at indoor speeds
#: (config/noise/paper.yaml, the fake calibrated to the paper's TurtleBot2i: E_s 0.5 %
#: plus slip 2 % per m/s, 0.7-1.3 % at 0.1-0.4 m/s; the datasheet-level kobuki profile
#: gives 0.3-0.6 %). gyro_noise_density: the Kobuki gyro's datasheet white noise,
#: ~0.03 deg/s/sqrt(Hz) (docs/fake_turtlebot.md). uncorrected_bias_std: a bias uniform
#: within the Kobuki gyro's +-5.8e-4 rad/s (config/noise/kobuki.yaml). uncorrected_scale_std:
#: the paper profile's gyro scale error (0.5 %; the fake's calibration measures 0.47 %).
DRIFT_DEFAULTS = {
    'wheel_error_per_m': 0.01,        # fraction: odometry distance error per metre driven
    'gyro_noise_density': 5.2e-4,     # rad/sqrt(s): the gyro heading's random walk
    'uncorrected_bias_std': 3.3e-4,   # rad/s: gyro bias std where the correction has none
    'uncorrected_scale_std': 0.005,   # gyro scale error std where the calibration has none
}


def drift_param(params, name, defaults=DRIFT_DEFAULTS):
    """``params.name`` (or the default), checked to be a finite number >= 0."""
    value = getattr(params, name, defaults[name]) if params is not None else defaults[name]
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError('%s must be a number, got %r' % (name, value))
    if not (value >= 0 and math.isfinite(value)):
        raise ValueError('%s must be a finite number >= 0, got %r' % (name, value))
    return value


class Drift(namedtuple('Drift', 'bias_x bias_y scale_x scale_y noise wheel')):
    """The drift of one loop (or of several, :meth:`plus`): the bias and scale
    sums (m s, m rad: vectors), the white-noise integral (m^2 s) and the wheel
    error's standard deviation (m)."""

    __slots__ = ()

    def plus(self, other):
        return Drift(*(a + b for a, b in zip(self, other)))


NO_DRIFT = Drift(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

LoopEstimate = namedtuple('LoopEstimate', 'length duration gap drift')
LoopEstimate.__doc__ = ('One loop: its length along the route (m), duration (s, recording time), '
                        'the odometry gap between its two passes (m) and its Drift.')


class LoopDrift(object):
    """The drift model of one route (module docstring). ``landmarks``: the
    route's landmarks (recording order, the frame the route was built in);
    ``correction``: core/heading_correction.GyroCorrection applied to them, or
    None (no heading correction); ``params``: :data:`DRIFT_DEFAULTS` attributes."""

    def __init__(self, route, landmarks, correction=None, params=None):
        landmarks = list(landmarks)
        if len(landmarks) != len(route.sections):
            raise ValueError('loop drift: %d landmarks for a route of %d sections'
                             % (len(landmarks), len(route.sections)))
        self.route = route
        self.bias_std = _std(correction, 'bias_std', drift_param(params, 'uncorrected_bias_std'))
        self.scale_std = _std(correction, 'scale_std', drift_param(params, 'uncorrected_scale_std'))
        self.noise_density = drift_param(params, 'gyro_noise_density')
        self.wheel_error = drift_param(params, 'wheel_error_per_m')
        self.arrive, self.leave = vertex_passes(route, landmarks)
        self._sums()

    def _sums(self):
        """Prefix sums over the elements of the route (element v: standing at vertex v,
        then the segment from v + 1 to v in recording order)."""
        route, arrive, leave = self.route, self.arrive, self.leave
        ox, oy = route.x[0], route.y[0]
        keys = ('gx', 'gy', 'tx', 'ty', 'hx', 'hy', 'c', 'dx', 'dy', 'f')
        sums = {k: [0.0] for k in keys}
        self.stand = []
        for v in range(route.vertices):
            x, y = route.x[v] - ox, route.y[v] - oy
            stood = max(0.0, leave[v][0] - arrive[v][0])
            self.stand.append((stood, stood * x, stood * y, stood * (x * x + y * y)))
            add = dict.fromkeys(keys, 0.0)
            add['c'], add['dx'], add['dy'], add['f'] = self.stand[-1]
            if v + 1 < route.vertices:
                gx, gy = route.x[v] - route.x[v + 1], route.y[v] - route.y[v + 1]
                t_mid = (leave[v + 1][0] + arrive[v][0]) / 2.0
                h_mid = (leave[v + 1][1] + arrive[v][1]) / 2.0
                dt = max(0.0, arrive[v][0] - leave[v + 1][0])
                mx, my = x - gx / 2.0, y - gy / 2.0
                add.update(gx=gx, gy=gy, tx=t_mid * gx, ty=t_mid * gy, hx=h_mid * gx, hy=h_mid * gy)
                add['c'] += dt
                add['dx'] += dt * mx
                add['dy'] += dt * my
                add['f'] += dt * (mx * mx + my * my)
            for k in keys:
                sums[k].append(sums[k][-1] + add[k])
        self._prefix = sums
        self._origin = (ox, oy)

    def _between(self, name, u, w):
        return self._prefix[name][w] - self._prefix[name][u]

    def loop(self, u, w):
        """:class:`LoopEstimate` of the loop from vertex ``w`` (earlier pass) to
        ``u`` (later pass), ``u < w`` (return order)."""
        if not 0 <= u < w < self.route.vertices:
            raise ValueError('loop drift: need 0 <= later %d < earlier %d < %d vertices'
                             % (u, w, self.route.vertices))
        route = self.route
        gx, gy = self._between('gx', u, w), self._between('gy', u, w)
        t_ref, h_ref = self.leave[w]
        bias = (self._between('tx', u, w) - t_ref * gx, self._between('ty', u, w) - t_ref * gy)
        scale = (self._between('hx', u, w) - h_ref * gx, self._between('hy', u, w) - h_ref * gy)
        stood = self.stand[u]        # standing at u comes after the loop: not in it
        c = self._between('c', u, w) - stood[0]
        dx, dy = self._between('dx', u, w) - stood[1], self._between('dy', u, w) - stood[2]
        f = self._between('f', u, w) - stood[3]
        ux, uy = route.x[u] - self._origin[0], route.y[u] - self._origin[1]
        noise = max(0.0, c * (ux * ux + uy * uy) - 2.0 * (ux * dx + uy * dy) + f)
        length = route.s[w] - route.s[u]
        drift = Drift(bias[0], bias[1], scale[0], scale[1], noise, self.wheel_error * length)
        return LoopEstimate(length, self.arrive[u][0] - t_ref,
                            math.hypot(route.x[u] - route.x[w], route.y[u] - route.y[w]), drift)

    def sigma(self, drift):
        """Standard deviation (m) of the true offset between the passes for ``drift``."""
        bias = self.bias_std * math.hypot(drift.bias_x, drift.bias_y)
        scale = self.scale_std * math.hypot(drift.scale_x, drift.scale_y)
        return math.sqrt(bias * bias + scale * scale + self.noise_density ** 2 * drift.noise
                         + drift.wheel * drift.wheel)


def _std(correction, name, prior):
    """The correction's std of a term, or ``prior`` where it did not correct that term."""
    value = getattr(correction, name, math.inf) if correction is not None else math.inf
    return value if math.isfinite(value) else prior


def vertex_passes(route, landmarks):
    """Per route vertex (return order): (recording time s, unwrapped heading rad)
    when the robot reached it and when it left it (module docstring)."""
    n = len(landmarks)
    times, headings = [], []
    elapsed = heading = 0.0
    for k, landmark in enumerate(landmarks):
        elapsed += landmark.T
        heading = landmark.psi if k == 0 else heading + period_turn(landmarks[k - 1], landmark)
        times.append(elapsed)
        headings.append(heading)
    start_heading = headings[0] - landmarks[0].w * landmarks[0].T if n else 0.0
    arrive, leave = [None] * route.vertices, [None] * route.vertices

    def note(vertex, t, h):
        if arrive[vertex] is None or t < arrive[vertex][0]:
            arrive[vertex] = (t, h)
        if leave[vertex] is None or t > leave[vertex][0]:
            leave[vertex] = (t, h)

    start = 0
    for index, section in enumerate(route.sections):
        k = n - 1 - index
        late = (times[k], headings[k])
        early = (times[k - 1], headings[k - 1]) if k > 0 else (0.0, start_heading)
        end = section.end_vertex
        if end == start:
            note(start, *late)
            note(start, *early)
        span = route.s[end] - route.s[start]
        for vertex in range(start, end + 1) if end > start else ():
            share = (route.s[vertex] - route.s[start]) / span if span > 0 else \
                (vertex - start) / float(end - start)
            note(vertex, late[0] + share * (early[0] - late[0]), late[1] + share * (early[1] - late[1]))
        start = end
    if not route.sections:
        note(0, 0.0, 0.0)
    missing = [v for v in range(route.vertices) if arrive[v] is None]
    if missing:
        raise ValueError('loop drift: route vertices %s belong to no section' % missing[:5])
    return arrive, leave

"""Pruning of the closed-loop return: :func:`prune_route` cuts loops where the path comes
back within ``prune_radius`` of a place it passed, if ``gap + prune_sigmas x drift std <=
prune_radius`` (:class:`LoopDrift`: the odometry drift over a loop); docs/pruning.md."""
import bisect
import math
from collections import namedtuple
from itertools import accumulate

from .period_model import period_turn
from .route import ROUTE_DEFAULTS, Route, Section, corner_turn

#: Defaults of the pruning and of its odometry error model over a loop (sources: docs/pruning.md).
PRUNE_DEFAULTS = {
    'wheel_error_per_m': 0.01,        # fraction: odometry distance error per metre driven
    'gyro_noise_density': 5.2e-4,     # rad/sqrt(s): the gyro heading's random walk
    'uncorrected_bias_std': 3.3e-4,   # rad/s: gyro bias std where the correction has none
    'uncorrected_scale_std': 0.005,   # gyro scale error std where the calibration has none
    'prune_radius': 0.175,     # m; two passes closer than this (plus the drift) are one place
    'prune_sigmas': 2.0,       # drift standard deviations the gap plus the drift must leave
    'prune_min_loop': 1.0,     # m; shorter loops are not cut (nothing worth the junction)
}


def drift_param(params, name, defaults=PRUNE_DEFAULTS):
    """``params.name`` (or the default), checked to be a finite number >= 0."""
    value = getattr(params, name, defaults[name])
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError('%s must be a number, got %r' % (name, value))
    if not (value >= 0 and math.isfinite(value)):
        raise ValueError('%s must be a finite number >= 0, got %r' % (name, value))
    return value


class Drift(namedtuple('Drift', 'bias_x bias_y scale_x scale_y noise wheel')):
    """Bias and scale sums (m s, m rad), white-noise integral (m^2 s), wheel error std (m)."""

    __slots__ = ()

    def plus(self, other):
        return Drift(*(a + b for a, b in zip(self, other)))


NO_DRIFT = Drift(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


class LoopDrift(object):
    """The drift model of ``route`` over ``landmarks`` corrected by ``correction`` (or None)."""

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
        """Prefix sums per vertex v: standing at v, then the segment from v + 1 to v."""
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
        """(duration s, :class:`Drift`) of the loop from vertex ``w`` back to ``u < w``."""
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
        wheel = self.wheel_error * (route.s[w] - route.s[u])
        return self.arrive[u][0] - t_ref, Drift(bias[0], bias[1], scale[0], scale[1], noise, wheel)

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
    """Per route vertex: (recording time s, unwrapped heading rad) reaching and leaving it."""
    n = len(landmarks)
    turns = [period_turn(a, b) for a, b in zip(landmarks, landmarks[1:])]
    times = list(accumulate(landmark.T for landmark in landmarks))
    headings = list(accumulate([landmark.psi for landmark in landmarks[:1]] + turns))
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


class Cut(namedtuple('Cut', 'later earlier share later_xy earlier_xy gap length duration sigma '
                            'sigma_total drift started')):
    """A candidate loop from vertex ``later`` back to ``share`` of the segment after vertex
    ``earlier`` (return order), its ``gap``, ``length``, ``duration``, drift std alone and
    with the cuts before (``sigma``, ``sigma_total``), Drift, and recording time ``started``."""

    __slots__ = ()

    landing = property(lambda self: (self.earlier, self.share))
    resume = property(lambda self: self.earlier + 1 if self.share > 0 else self.earlier)
    saved = property(lambda self: self.length - self.gap)

    def describe(self, params=None):
        text = ('a %.2f m, %.0f s loop (recorded from %.0f s) from (%.2f, %.2f) back to (%.2f, %.2f): '
                'gap %.3f m, drift std %.3f m (%.3f m with the cuts before)' % (
                    self.length, self.duration, self.started, self.later_xy[0], self.later_xy[1],
                    self.earlier_xy[0], self.earlier_xy[1], self.gap, self.sigma, self.sigma_total))
        if params is None:
            return text
        return text + ': gap + %g x %.3f = %.3f m > prune_radius %.3f m' % (
            params['prune_sigmas'], self.sigma_total,
            self.gap + params['prune_sigmas'] * self.sigma_total, params['prune_radius'])


class PruneResult(namedtuple('PruneResult', 'route cuts refused params examined')):
    """The pruned route, cuts, refused candidates, params and vertices examined."""

    __slots__ = ()

    saved = property(lambda self: sum(cut.saved for cut in self.cuts))

    def describe(self):
        lines = ['cut %s; saves %.2f m' % (cut.describe(), cut.saved) for cut in self.cuts]
        lines += ['refused %s' % cut.describe(self.params) for cut in self.refused]
        lines.append('pruning: %d cut(s), %d refused, route %.2f m' % (
            len(self.cuts), len(self.refused), self.route.length))
        return lines


def prune_route(route, landmarks, correction=None, params=None):
    """:class:`PruneResult` of ``route`` built from ``landmarks`` in the frame of ``correction``."""
    values = {name: drift_param(params, name) for name in PRUNE_DEFAULTS}
    if not values['prune_radius'] > 0:
        raise ValueError('prune_radius must be > 0, got %r' % values['prune_radius'])
    drift = LoopDrift(route, landmarks, correction, params)
    radius, sigmas, min_loop = values['prune_radius'], values['prune_sigmas'], values['prune_min_loop']
    near, scanned = _neighbours(route, radius, min_loop)
    cuts, refused = [], []

    def candidate(u, landing, before):
        index, share = landing
        start = index + 1 if share > 0 else index       # the loop taken to the segment's far end
        duration, loop_drift = drift.loop(u, start)
        total = before.plus(loop_drift)
        x, y = _point(route, index, share)
        along = route.s[index] + share * (route.s[start] - route.s[index])
        gap = math.hypot(x - route.x[u], y - route.y[u])
        cut = Cut(u, index, share, (route.x[u], route.y[u]), (x, y), gap, along - route.s[u], duration,
                  drift.sigma(loop_drift), drift.sigma(total), total, drift.leave[start][0])
        return cut, gap + sigmas * cut.sigma_total <= radius

    u, last, carried = 0, route.vertices - 1, NO_DRIFT
    while u < last:
        accepted = rejected = None
        for landing in _landings(route, u, near(u)):
            cut, ok = candidate(u, landing, carried)
            if cut.gap > radius or cut.length < min_loop:
                continue
            if ok:
                if accepted is None or landing > accepted.landing:
                    accepted = cut
            elif rejected is None or landing > rejected.landing:
                rejected = cut
        if rejected is not None and (accepted is None or rejected.landing > accepted.landing):
            refused.append(rejected)
        if accepted is not None and cuts and cuts[-1].resume == u:
            # landed on a junction and jumping on at once: one chord for both, if it fits
            merged, ok = candidate(cuts[-1].later, accepted.landing, cuts[-2].drift if len(cuts) > 1 else NO_DRIFT)
            if ok:
                cuts.pop()
                accepted = merged
        if accepted is not None:
            cuts.append(accepted)
            carried, u = accepted.drift, accepted.resume
        else:
            u += 1
    pruned = apply_cuts(route, cuts, params) if cuts else route
    return PruneResult(pruned, cuts, _one_per_loop(refused), values, scanned[0])


def _point(route, index, share):
    if share <= 0:
        return route.x[index], route.y[index]
    return (route.x[index] + share * (route.x[index + 1] - route.x[index]),
            route.y[index] + share * (route.y[index + 1] - route.y[index]))


def _landings(route, u, vertices):
    """(vertex, share) where a cut from ``u`` can land: each nearby vertex's segments' nearest point."""
    x, y, last = route.x[u], route.y[u], route.vertices - 1
    seen = set()
    for w in vertices:
        for a in (w - 1, w):
            if a <= u or a + 1 > last:
                continue
            dx, dy = route.x[a + 1] - route.x[a], route.y[a + 1] - route.y[a]
            length_sq = dx * dx + dy * dy
            share = ((x - route.x[a]) * dx + (y - route.y[a]) * dy) / length_sq if length_sq > 0 else 0.0
            landing = (a + 1, 0.0) if share >= 1.0 else (a, max(0.0, share))
            if landing not in seen:
                seen.add(landing)
                yield landing
        if w == last and (w, 0.0) not in seen:
            seen.add((w, 0.0))
            yield (w, 0.0)


def _neighbours(route, radius, min_loop):
    """(``near(u)``: vertices within ``radius``, ``min_loop`` on; [entries scanned])."""
    cells = {}
    for vertex, (x, y) in enumerate(zip(route.x, route.y)):
        cells.setdefault((math.floor(x / radius), math.floor(y / radius)), []).append(vertex)
    s, scanned = route.s, [0]
    # each cell's route positions, to bisect on (bisect's key= is Python 3.10+)
    positions = {key: [s[v] for v in cell] for key, cell in cells.items()}

    def near(u):
        x, y = route.x[u], route.y[u]
        cx, cy = math.floor(x / radius), math.floor(y / radius)
        for i in (cx - 1, cx, cx + 1):
            for j in (cy - 1, cy, cy + 1):
                cell = cells.get((i, j))
                if not cell:
                    continue
                first = bisect.bisect_left(positions[(i, j)], s[u] + min_loop)
                for w in cell[max(first, bisect.bisect_right(cell, u)):]:
                    scanned[0] += 1
                    if math.hypot(route.x[w] - x, route.y[w] - y) <= radius:
                        yield w
    return near, scanned


def _one_per_loop(refused):
    """Refused candidates of consecutive vertices are one candidate loop: keep the largest."""
    loops = []
    for cut in refused:
        if loops and cut.later - loops[-1][-1].later <= 1:
            loops[-1].append(cut)
        else:
            loops.append([cut])
    return [max(run, key=lambda c: c.saved) for run in loops]


def apply_cuts(route, cuts, params=None):
    """The Route without the loops of ``cuts`` (return order): sections inside a cut end at
    its junction, a corner; a landing within a segment becomes a vertex."""
    merge = drift_param(params, 'merge_distance', ROUTE_DEFAULTS)
    corner_angle = drift_param(params, 'corner_angle', ROUTE_DEFAULTS)
    slowest_v = drift_param(params, 'slowest_v', ROUTE_DEFAULTS)
    keep, junctions, landed, new_of, inside = [], [], [], {}, {}
    start = 0
    for cut in cuts:        # keep: original vertex indices, or a cut (its landing point)
        if not (start <= cut.later < cut.earlier < route.vertices and 0.0 <= cut.share < 1.0):
            raise ValueError('cut %d -> %d (share %r) does not follow the previous one (at %d)'
                             % (cut.later, cut.earlier, cut.share, start))
        keep.extend(range(start, cut.later if cut.gap < merge else cut.later + 1))
        if cut.share > 0:
            keep.append(cut)
        if cut.gap < merge:         # the passes coincide: the landing point is the junction
            new_of[cut.later] = len(keep) - (1 if cut.share > 0 else 0)
            junction = new_of[cut.later]
        else:
            junction = len(keep) - (2 if cut.share > 0 else 1)
        junctions.append((junction, cut))
        landed.append(junction + (0 if cut.gap < merge else 1))
        for vertex in range(cut.later + 1, cut.resume if cut.share > 0 else cut.earlier):
            inside[vertex] = junction
        start = cut.resume
    keep.extend(range(start, route.vertices))
    for index, vertex in enumerate(keep):
        if not isinstance(vertex, Cut):
            new_of.setdefault(vertex, index)
    xs = [v.earlier_xy[0] if isinstance(v, Cut) else route.x[v] for v in keep]
    ys = [v.earlier_xy[1] if isinstance(v, Cut) else route.y[v] for v in keep]
    speeds = [route.speed[v.earlier] + v.share * (route.speed[v.earlier + 1] - route.speed[v.earlier])
              if isinstance(v, Cut) else route.speed[v] for v in keep]
    corner = [False if isinstance(v, Cut) else route.corner[v] for v in keep]
    for (junction, _), landing in zip(junctions, landed):
        corner[junction] = True
        if landing != junction and 0 < landing < len(keep) - 1 and landing not in [j for j, _ in junctions]:
            corner[landing] = abs(corner_turn(xs, ys, landing)) > corner_angle
    sections, previous, pending = [], (0, 0.0), list(junctions)
    for section in route.sections:
        if section.end_vertex in inside:    # done on arrival at the junction
            mark, nominal, turn = max((inside[section.end_vertex], 0.0), previous), 0.0, 0.0
        else:
            mark = max((new_of[section.end_vertex], section.end_phase), previous)
            nominal, turn = section.nominal_time, section.turn
            while pending and mark[0] > pending[0][0]:     # this section drives the chord
                junction, cut = pending.pop(0)
                turn += abs(corner_turn(xs, ys, junction))
                if junction + 1 < len(corner) and corner[junction + 1]:
                    turn += abs(corner_turn(xs, ys, junction + 1))
                nominal += cut.gap / max(section.speed, slowest_v)
        sections.append(Section(mark[0], mark[1], section.speed, section.turn_rate, nominal, turn))
        previous = mark
    return Route(xs, ys, speeds, corner, sections)

"""Pruning of the closed-loop return: cut loops and doubled-back stretches where the
path comes back within ``prune_radius`` of a place it passed, only where the drift allows.

``prune_route(route, landmarks, correction, params)`` -> ``.route`` (pruned), ``.cuts``,
``.refused``, ``.describe()``. Rule: ``gap + prune_sigmas x drift std <= prune_radius``
(core/loop_drift.py); one section per landmark is kept (docs/pruning.md).
"""
import bisect
import math
from collections import namedtuple

from .loop_drift import DRIFT_DEFAULTS, NO_DRIFT, LoopDrift, drift_param
from .route import ROUTE_DEFAULTS, Route, Section, corner_turn

#: Defaults of the pruning (the back-travel client exposes them as ~params); with the
#: drift model's (core/loop_drift.DRIFT_DEFAULTS).
PRUNE_DEFAULTS = dict(DRIFT_DEFAULTS, **{
    'prune_radius': 0.175,     # m; two passes closer than this (plus the drift) are one place
    'prune_sigmas': 2.0,       # drift standard deviations the gap plus the drift must leave
    'prune_min_loop': 1.0,     # m; shorter loops are not cut (nothing worth the junction)
})


class Cut(namedtuple('Cut', 'later earlier share later_xy earlier_xy gap length duration sigma '
                            'sigma_total drift started')):
    """A candidate loop: from vertex ``later`` of the unpruned route (return
    order) back to the earlier pass at ``share`` of the segment from vertex
    ``earlier`` to the next (0: the vertex itself), and their (x, y); the
    odometry ``gap`` (m), the loop's ``length`` (m) and ``duration`` (s); the
    drift std of this loop alone (``sigma``, m) and with the cuts before it
    (``sigma_total``, m); the accumulated core/loop_drift.Drift; when the loop
    ``started`` (s of recording time: the robot left the earlier pass). Length
    aside, the loop is taken to the segment's far end (conservative)."""

    __slots__ = ()

    @property
    def landing(self):
        """(vertex, share): where on the route the cut lands, comparable."""
        return self.earlier, self.share

    @property
    def resume(self):
        """The first vertex of the unpruned route the return drives after the cut."""
        return self.earlier + 1 if self.share > 0 else self.earlier

    @property
    def saved(self):
        """m of route the cut saves."""
        return self.length - self.gap

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
    """The pruned route, the cuts made, the candidates refused, the params used
    and how many nearby vertices the search looked at (its cost)."""

    __slots__ = ()

    @property
    def saved(self):
        return sum(cut.saved for cut in self.cuts)

    def describe(self):
        """Log lines: each cut, each refused candidate, and a summary."""
        lines = ['cut %s; saves %.2f m' % (cut.describe(), cut.saved) for cut in self.cuts]
        lines += ['refused %s' % cut.describe(self.params) for cut in self.refused]
        lines.append('pruning: %d cut(s), %d refused, route %.2f m' % (
            len(self.cuts), len(self.refused), self.route.length))
        return lines


def prune_params(params=None):
    """{name: value} of :data:`PRUNE_DEFAULTS` from ``params`` (attributes), checked."""
    values = {name: drift_param(params, name, PRUNE_DEFAULTS) for name in PRUNE_DEFAULTS}
    if not values['prune_radius'] > 0:
        raise ValueError('prune_radius must be > 0, got %r' % values['prune_radius'])
    return values


def prune_route(route, landmarks, correction=None, params=None):
    """:class:`PruneResult` of ``route`` (core/route.Route built from ``landmarks``,
    recording order, in the frame of ``correction``, a GyroCorrection or None);
    ``params``: attributes of :data:`PRUNE_DEFAULTS` and core/route.ROUTE_DEFAULTS."""
    values = prune_params(params)
    drift = LoopDrift(route, landmarks, correction, params)
    radius, sigmas, min_loop = values['prune_radius'], values['prune_sigmas'], values['prune_min_loop']
    near, scanned = _neighbours(route, radius, min_loop)
    cuts, refused = [], []

    def candidate(u, landing, before):
        index, share = landing
        start = index + 1 if share > 0 else index       # the loop taken to the segment's far end
        loop = drift.loop(u, start)
        total = before.plus(loop.drift)
        x, y = _point(route, index, share)
        along = route.s[index] + share * (route.s[start] - route.s[index])
        gap = math.hypot(x - route.x[u], y - route.y[u])
        cut = Cut(u, index, share, (route.x[u], route.y[u]), (x, y), gap, along - route.s[u], loop.duration,
                  drift.sigma(loop.drift), drift.sigma(total), total, drift.leave[start][0])
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
    """Where on the earlier passes near vertex ``u`` a cut can land: for each nearby
    vertex, the point of each of its two segments nearest ``u``, as (vertex, share)."""
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
    """(``near(u)``: the vertices ``w > u`` within ``radius`` of vertex ``u`` and at
    least ``min_loop`` further along the route, from a grid of ``radius`` cells;
    [how many cell entries it looked at])."""
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
    """The :class:`~core.route.Route` without the loops of ``cuts`` (return order,
    each starting at or after where the previous one resumes; module docstring:
    sections inside a cut end at its junction, which is a corner; a cut landing
    within a segment adds its landing point as a vertex)."""
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

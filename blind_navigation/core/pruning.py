"""Pruning of the closed-loop return: cut loops and doubled-back stretches where
the recorded path comes back to a place it passed before, only through space
the robot drove, and only where the drift over the loop allows it.

API (the back-travel client and the harness, after core/route.build_route)::

    result = prune_route(route, landmarks, correction, params)
    result.route        # the route the return drives (``route`` itself when nothing was cut)
    result.cuts         # [Cut] made, in return order
    result.refused      # [Cut] candidate loops refused for their drift (one per candidate)
    result.describe()   # one line per cut and refused candidate, for the log

**Where.** The route (return order: vertex 0 is where recording stopped, the
last vertex the start) is the recorded path in the corrected odometry frame.
Walking it from the anchor, at each vertex ``u`` the earlier passes within
``prune_radius`` (a grid of cells that size: each vertex looks at nine cells)
that are at least ``prune_min_loop`` further along the route are candidate
junctions ``w``: the path between them (recorded from ``w`` to ``u``) is a loop,
an out-and-back corridor, a dead end backed out of, or everything since the
start when the path passes the start again. The return goes from ``u``
straight to ``w``, the junction's chord, and on from there: it passes only
through recorded points, and the chord joins two passes within the radius.

**Why the radius.** ``prune_radius`` is half the Kobuki's 0.35 m footprint:
while the robot's centre moves along a chord of at most that length between
two passes, it stays within a quarter footprint (0.09 m) of one of them, so
its body stays inside the band the two passes' bodies swept but for a sliver
of at most that; a larger radius lets the chord's sweep reach a full radius
beyond it (and a door a robot passes twice is still crossed where the passes
meet).

**The rule (honest about drift).** Odometry's ``gap`` is not the truth: the two
passes are truly apart by the gap plus the drift gathered over the loop
(core/loop_drift.py: gyro bias and scale left after the heading correction and
calibration, gyro white noise, wheel error per metre; a robot that already
skipped loops carries their drift too, so each candidate is judged with the
drift of every cut before it). A cut is made only when
``gap + prune_sigmas x drift std <= prune_radius``: with ``prune_sigmas`` 2, at
least 95 % sure the true passes are within the radius. Among a vertex's
candidates the one furthest along (the most saved) is cut; candidates
refused are reported, one per candidate loop (the largest of a run of
vertices).

**The protocol stays.** The route keeps one section per landmark: a section
that ended inside a cut now ends at the junction, on arrival (the goals of the
cut follow one another there), the junction is a corner (the robot stops
there, so those goals are handed over while it stands, then turns onto the
chord), and the sections after it end where they did. So the client still
sends every landmark as a goal, the progress counts stay right, and a resumed
return follows the same (pruned) route from its progress file.

Cost: O(n) to set up, then O(number of nearby vertices) per vertex walked:
linear in the landmark count for paths that pass each place a bounded number
of times. The follower's cost per control step does not change.

``time`` and ``distance`` replay landmarks open loop and cannot prune: only
``closed_loop`` drives this route.
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


class Cut(namedtuple('Cut', 'later earlier later_xy earlier_xy gap length duration sigma '
                            'sigma_total drift started')):
    """A candidate loop: vertices ``later`` < ``earlier`` of the unpruned route
    (return order) and their (x, y); the odometry ``gap`` (m), the loop's
    ``length`` (m) and ``duration`` (s); the drift std of this loop alone
    (``sigma``, m) and with the cuts before it (``sigma_total``, m); the
    accumulated core/loop_drift.Drift; when the loop ``started`` (s of recording
    time: the robot left the earlier pass's vertex)."""

    __slots__ = ()

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
    near, scanned = _neighbours(route, values['prune_radius'], values['prune_min_loop'])
    radius, sigmas = values['prune_radius'], values['prune_sigmas']
    cuts, refused = [], []
    carried = NO_DRIFT
    u, last = 0, route.vertices - 1
    while u < last:
        accepted = rejected = None
        for w in near(u):
            loop = drift.loop(u, w)
            total = carried.plus(loop.drift)
            cut = Cut(u, w, (route.x[u], route.y[u]), (route.x[w], route.y[w]), loop.gap, loop.length,
                      loop.duration, drift.sigma(loop.drift), drift.sigma(total), total, drift.leave[w][0])
            if cut.gap + sigmas * cut.sigma_total <= radius:
                if accepted is None or w > accepted.earlier:
                    accepted = cut
            elif rejected is None or w > rejected.earlier:
                rejected = cut
        if rejected is not None and (accepted is None or rejected.earlier > accepted.earlier):
            refused.append(rejected)
        if accepted is not None:
            cuts.append(accepted)
            carried, u = accepted.drift, accepted.earlier
        else:
            u += 1
    pruned = apply_cuts(route, cuts, params) if cuts else route
    return PruneResult(pruned, cuts, _one_per_loop(refused), values, scanned[0])


def _neighbours(route, radius, min_loop):
    """(``near(u)``: the vertices ``w > u`` within ``radius`` of vertex ``u`` and at
    least ``min_loop`` further along the route, from a grid of ``radius`` cells;
    [how many cell entries it looked at])."""
    cells = {}
    for vertex, (x, y) in enumerate(zip(route.x, route.y)):
        cells.setdefault((math.floor(x / radius), math.floor(y / radius)), []).append(vertex)
    s, scanned = route.s, [0]

    def near(u):
        x, y = route.x[u], route.y[u]
        cx, cy = math.floor(x / radius), math.floor(y / radius)
        for i in (cx - 1, cx, cx + 1):
            for j in (cy - 1, cy, cy + 1):
                cell = cells.get((i, j))
                if not cell:
                    continue
                first = bisect.bisect_left(cell, s[u] + min_loop, key=lambda v: s[v])
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
    each starting at or after the previous one's ``earlier`` vertex; module
    docstring: sections inside a cut end at its junction, which is a corner)."""
    merge = drift_param(params, 'merge_distance', ROUTE_DEFAULTS)
    corner_angle = drift_param(params, 'corner_angle', ROUTE_DEFAULTS)
    slowest_v = drift_param(params, 'slowest_v', ROUTE_DEFAULTS)
    keep, junctions, new_of = [], [], {}
    start = 0
    for cut in cuts:
        if not start <= cut.later < cut.earlier < route.vertices:
            raise ValueError('cut %d -> %d does not follow the previous one (at %d)'
                             % (cut.later, cut.earlier, start))
        if cut.gap < merge:         # the passes coincide: the earlier one's vertex is the junction
            keep.extend(range(start, cut.later))
            new_of[cut.later] = len(keep)
            junctions.append((len(keep), cut))
        else:
            keep.extend(range(start, cut.later + 1))
            junctions.append((len(keep) - 1, cut))
        start = cut.earlier
    keep.extend(range(start, route.vertices))
    for index, vertex in enumerate(keep):
        new_of.setdefault(vertex, index)
    xs, ys = [route.x[v] for v in keep], [route.y[v] for v in keep]
    speeds = [route.speed[v] for v in keep]
    corner = [route.corner[v] for v in keep]
    for junction, _ in junctions:
        corner[junction] = True
        after = junction + 1
        if after < len(keep) - 1 and not any(j == after for j, _ in junctions):
            corner[after] = abs(corner_turn(xs, ys, after)) > corner_angle
    inside = {}                     # an old vertex inside a cut -> the new junction vertex
    for junction, cut in junctions:
        for vertex in range(cut.later + 1, cut.earlier):
            inside[vertex] = junction
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

#!/usr/bin/env python3
"""The margins of the `home` invariant (docs/safety.md, "home"), measured in the harness:
closed-loop returns on seeded random paths of every category (sim/random_paths), paper
noise, on the kinematic or the MuJoCo base. Per run: the outcome, the follower's planned
stop from the route's end (finish_tolerance), the stopped robot's distance from it by the
return's odometry (home_tolerance) and the largest distance from the route on the way
(route_max_offset).

    /usr/bin/python3 scripts/home_margins.py FIRST_SEED COUNT [kinematic|mujoco]
"""
import sys

from blind_navigation.core import mission as core_mission
from blind_navigation.core.geometry import distance
from blind_navigation.core.route_follower import RouteFollower
from blind_navigation.evaluation.montecarlo import settings_for
from blind_navigation.sim import harness
from blind_navigation.sim.random_paths import CATEGORIES, LOOP_CATEGORIES, random_mission


class MeasuredFollower(RouteFollower):
    """A RouteFollower that keeps its planned stop's and its largest route offsets."""
    last = None

    def __init__(self, route, params=None):
        super(MeasuredFollower, self).__init__(route, params)
        self.planned_stop = self.widest = None
        MeasuredFollower.last = self

    def _finish(self, odom):
        self.planned_stop = self.off_end(odom)
        return super(MeasuredFollower, self)._finish(odom)

    def _locate(self, x, y):
        along, off = super(MeasuredFollower, self)._locate(x, y)
        self.widest = max(self.widest or 0.0, off)
        return along, off


def main(first, count, base='kinematic'):
    core_mission.RouteFollower = MeasuredFollower
    categories = sorted(CATEGORIES) + sorted(LOOP_CATEGORIES)
    for seed in range(first, first + count):
        category = categories[seed % len(categories)]
        stopped = []
        _stop = harness._stop

        def stop(run, mission, settings):
            _stop(run, mission, settings)
            route = MeasuredFollower.last.route
            odom = mission.odom()
            stopped.append(distance(odom.x, odom.y, route.x[-1], route.y[-1]))
        harness._stop = stop
        try:
            result = harness.run_modes(random_mission(category, seed), 'paper', ('closed_loop',), seed,
                                       settings_of=settings_for('paper', seed, base))['closed_loop']
        finally:
            harness._stop = _stop
        follower = MeasuredFollower.last
        print('%-14s %4d %-7s %6.2f m  true error %.3f m  planned stop %s  stopped %.3f m  '
              'widest off the route %.3f m  %s' % (
                  category, seed, result.status, result.distance, result.position_error,
                  '%.3f m' % follower.planned_stop if follower.planned_stop is not None else '-',
                  stopped[-1] if stopped else float('nan'), follower.widest or 0.0,
                  result.reason[:90]), flush=True)


if __name__ == '__main__':
    main(int(sys.argv[1]), int(sys.argv[2]), *sys.argv[3:4])

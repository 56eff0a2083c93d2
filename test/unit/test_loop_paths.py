"""Paths that come back to where they have been (sim/random_paths.LOOP_CATEGORIES),
driven as plans on ground truth (sim/path_tracker.py), and the harness's
``prune_loops``: seeded, within their lengths and the Kobuki's limits, the plans
really revisit places (and the tracked robot with them), the older categories
are what they were, and a pruned return on the paper profile comes home along
its shorter route from the same recording as the unpruned one."""
import hashlib
import math

import pytest

from blind_navigation.sim.harness import run_modes
from blind_navigation.sim.kobuki import arc_motion
from blind_navigation.sim.path_tracker import TrackedSeries
from blind_navigation.sim.random_paths import LOOP_CATEGORIES, random_mission

from test_paths import seeded_within_category

SETTINGS = {'heading_correction': False, 'floor': False, 'event_sampling': True}


def plan_points(mission, step=0.05):
    """(s, x, y) along the plan, every ``step`` m or so."""
    x = y = yaw = s = 0.0
    points = [(0.0, 0.0, 0.0)]
    for v, w, duration in mission.segments:
        pieces = max(1, int(abs(v) * duration / step))
        for _ in range(pieces):
            x, y, yaw = arc_motion(x, y, yaw, v, w, duration / pieces)
            s += abs(v) * duration / pieces
            points.append((s, x, y))
    return points


def closest_return(points, later_than=2.0):
    """Smallest distance between two plan points more than ``later_than`` m apart along it."""
    best = math.inf
    for i, (s, x, y) in enumerate(points):
        for s2, x2, y2 in points[i + 1:]:
            if s2 - s > later_than:
                best = min(best, math.hypot(x2 - x, y2 - y))
    return best


@pytest.mark.parametrize('category', sorted(LOOP_CATEGORIES))
def test_loop_paths_are_seeded_within_their_lengths_and_come_back(category):
    missions = seeded_within_category(LOOP_CATEGORIES, category, 4)
    for seed, mission in enumerate(missions):
        assert isinstance(mission, TrackedSeries)
        assert closest_return(plan_points(mission)) < 0.03, (category, seed)


def test_patrols_pass_the_start_again_and_dead_ends_are_backed_out_of():
    for seed in range(4):
        points = plan_points(random_mission('patrol', seed))
        assert min(math.hypot(x, y) for s, x, y in points if s > 3.0) < 0.03
        dead_end = random_mission('dead_end', seed)
        assert any(v < 0 for v, _, _ in dead_end.segments)


#: sha256 (first 16 hex digits) of the segments of the older categories at seeds 0 and
#: 1000, as they were before the loop categories were added.
OLDER = {('creeping', 0): '0d5d22a9e9982a07', ('creeping', 1000): '82ea515569f86c95',
         ('fast_long', 0): 'cebf46b8090ae6cf', ('fast_long', 1000): 'af2be811e71851c8',
         ('indoor_mixed', 0): '04e1c06db95f6efd', ('indoor_mixed', 1000): 'edf0b4ed655b89a7',
         ('move_base_like', 0): '2cf9beb6df7a04f4', ('move_base_like', 1000): '267d0cd07bd72dc7',
         ('reversing', 0): 'ca4f6e410c014e5a', ('reversing', 1000): 'f5242a6ab8c97f22',
         ('turns_in_place', 0): 'cb36730e71185627', ('turns_in_place', 1000): 'ad1980487372e4d0'}


@pytest.mark.parametrize('category, seed', sorted(OLDER))
def test_the_older_categories_give_what_they_gave(category, seed):
    segments = random_mission(category, seed).segments
    assert hashlib.sha256(repr(segments).encode()).hexdigest()[:16] == OLDER[(category, seed)]


def test_a_pruned_return_comes_home_along_its_shorter_route_from_the_same_recording():
    mission = random_mission('dead_end', 2)
    results = run_modes(mission, 'paper', ('unpruned', 'pruned'), 2, run_mode=lambda mode: 'closed_loop',
                        settings_of=lambda mode: dict(SETTINGS, prune_loops=mode == 'pruned'))
    unpruned, pruned = results['unpruned'], results['pruned']
    assert unpruned.landmarks == pruned.landmarks and unpruned.pruning is None
    assert pruned.status == 'home', pruned.reason
    assert pruned.pruning.cuts and pruned.route_length < 0.7 * unpruned.route_length
    assert pruned.return_length == pytest.approx(pruned.route_length, rel=0.05)
    assert unpruned.return_length == pytest.approx(unpruned.route_length, rel=0.05)
    assert pruned.return_time < unpruned.return_time
    assert pruned.position_error < 0.05 * pruned.distance


def test_the_tracked_robot_really_closes_its_loops():
    mission = random_mission('figure_eight', 2)
    result = run_modes(mission, 'paper', ('closed_loop',), 2, settings_of=lambda mode: SETTINGS)
    path = result['closed_loop'].forward_path
    along, points = 0.0, [(0.0, path[0][0], path[0][1])]
    for (x0, y0), (x1, y1) in zip(path, path[1:]):
        along += math.hypot(x1 - x0, y1 - y0)
        points.append((along, x1, y1))
    assert closest_return(points[::4]) < 0.05

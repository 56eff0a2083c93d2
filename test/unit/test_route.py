"""The whole return route (core/route.py): built from landmarks recorded on an
exact unicycle, it runs back through the recorded path (arcs, reversing, turns
in place, pauses), marks corners where the robot turned in place or reversed,
ends each landmark's section where the landmark was taken, survives a round
trip through its plain form, and is built in linear time."""
import math

import pytest

from blind_navigation.core import route as route_module
from blind_navigation.core.geometry import wrap_angle
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.period_model import period_shape, period_turn
from blind_navigation.core.route import Route, build_route

from unicycle import drive, record

LEFT_ARC = [(0.2, 0.4, 6.0)]
CORNER = [(0.2, 0.0, 6.0), (0.0, 0.5, math.pi), (0.2, 0.0, 6.0)]          # turn 90 deg in place
REVERSING = [(0.2, 0.0, 6.0), (0.0, 0.0, 2.0), (-0.15, 0.0, 4.0)]         # stop, back up
PAUSED = [(0.2, 0.1, 4.0), (0.0, 0.0, 6.0), (0.2, -0.1, 4.0)]


def true_path(profile, step=0.01):
    odom_at, duration = drive(profile)
    return [odom_at(k * step) for k in range(int(duration / step) + 1)]


def distance_to_path(point, path):
    return min(math.hypot(point[0] - s.x, point[1] - s.y) for s in path)


def built(profile, **record_options):
    landmarks, end = record(profile, **record_options)
    return landmarks, build_route(landmarks, (end.x, end.y))


# (profile, tolerance m): after the corner's turn in place the robot drives off within
# the same 2 s period; from the landmarks alone (no sample when it set off) that
# period's chord is uncertain by a few degrees: 1.7 cm here.
@pytest.mark.parametrize('profile, tolerance', [(LEFT_ARC, 0.01), (CORNER, 0.02), (REVERSING, 0.01),
                                                (PAUSED, 0.01)],
                         ids=['arc', 'corner', 'reversing', 'paused'])
def test_route_runs_back_through_the_recorded_path_to_the_start(profile, tolerance):
    landmarks, route = built(profile)
    assert math.hypot(route.x[-1], route.y[-1]) < tolerance
    path = true_path(profile)
    worst = max(distance_to_path(p, path) for p in zip(route.x, route.y))
    assert worst < tolerance, worst
    assert len(route.sections) == len(landmarks)


def test_arc_points_follow_the_arc_not_its_chords():
    # 0.4 rad/s sampled at 1 s: chords cut 2 cm inside a 0.5 m radius arc; the
    # modelled points lie on the arc.
    _, route = built(LEFT_ARC)
    radius = 0.2 / 0.4
    gaps = [abs(math.hypot(x, y - radius) - radius) for x, y in zip(route.x, route.y)]
    assert max(gaps) < 0.002
    assert route.vertices > 3 * 6


def test_a_turn_in_place_is_a_corner_with_heading_goals():
    landmarks, route = built(CORNER)
    inner = [i for i in route.corners if 0 < i < route.vertices - 1]
    assert len(inner) == 1
    corner = inner[0]
    assert math.hypot(route.x[corner] - 1.2, route.y[corner]) < 0.02
    # (the corner's own angle is below pi / 2 where the drive-off's period bends into it)
    turn = abs(route_module.corner_turn(route.x, route.y, corner))
    assert 1.0 < turn < math.pi / 2 + 0.05
    standing = [s for s in route.sections if s.end_vertex == corner and s.end_phase > 0]
    assert standing and standing[-1].end_phase == 1.0       # the last one finishes the turn
    phases = [s.end_phase for s in standing]
    assert phases == sorted(phases)
    assert sum(s.turn for s in standing) == pytest.approx(turn)


def test_reversing_is_retraced_in_its_direction_with_a_cusp_corner():
    landmarks, route = built(REVERSING)
    assert any(lm.v < 0 for lm in landmarks)
    # Back from the end of the reversed stretch (x = 0.6) to x = 1.2, then to the start.
    far = max(range(route.vertices), key=lambda i: route.x[i])
    assert route.x[far] == pytest.approx(1.2, abs=0.01)
    assert route.corner[far]
    assert all(route.x[i] <= route.x[i + 1] + 1e-9 for i in range(far))
    assert all(route.x[i] >= route.x[i + 1] - 1e-9 for i in range(far, route.vertices - 1))


def test_pauses_leave_no_zero_length_pieces_and_their_sections_end_on_arrival():
    landmarks, route = built(PAUSED)
    lengths = [b - a for a, b in zip(route.s, route.s[1:])]
    assert min(lengths) >= route_module.ROUTE_DEFAULTS['merge_distance'] - 1e-12
    still = [i for i, lm in enumerate(reversed(landmarks)) if lm.d == 0.0]
    assert still
    for index in still:
        assert route.sections[index].end_phase == 0.0


def test_sections_end_where_their_landmarks_were_taken():
    landmarks, route = built(PAUSED)
    odom_at, _ = drive(PAUSED)
    elapsed, ends = 0.0, []
    for lm in landmarks:
        elapsed += lm.T
        ends.append(odom_at(elapsed))
    for index, section in enumerate(route.sections[:-1]):
        taken = ends[len(landmarks) - 2 - index]          # the previous landmark's position
        vertex = section.end_vertex
        assert math.hypot(route.x[vertex] - taken.x, route.y[vertex] - taken.y) < 0.011


def test_no_landmarks_or_no_motion_gives_a_one_point_route():
    assert build_route([], (1.0, 2.0)).vertices == 1
    still = [Landmark(0.0, 0.0, 0.0, 2.0, 0.3)] * 5
    route = build_route(still, (1.0, 2.0))
    assert route.vertices == 1 and route.length == 0.0 and len(route.sections) == 5


def test_bad_anchor_or_landmark_is_refused_naming_it():
    with pytest.raises(ValueError, match='anchor'):
        build_route([], (float('nan'), 0.0))
    with pytest.raises(ValueError, match='landmark 2'):
        build_route([Landmark(0.1, 0, 0.1, 1, 0), Landmark(0.1, 0, -0.1, 1, 0)], (0, 0))


def test_plain_form_round_trip_and_bad_form():
    _, route = built(CORNER)
    data = route.to_lists()
    assert all(isinstance(v, float) for values in data.values() for v in values)
    again = Route.from_lists(data)
    assert again.x == route.x and again.corner == route.corner
    assert [again.section_end(i) for i in range(len(again.sections))] == \
        [route.section_end(i) for i in range(len(route.sections))]
    broken = dict(data, section_end_vertex=data['section_end_vertex'][:-1])
    with pytest.raises(ValueError, match='differ in length'):
        Route.from_lists(broken)
    with pytest.raises(ValueError, match='fields'):
        Route.from_lists({'x': [0.0]})
    with pytest.raises(ValueError, match='section_end_vertex'):
        Route.from_lists(dict(data, section_end_vertex=[0.5] * len(data['section_end_vertex'])))


def test_period_turn_unwraps_turns_faster_than_pi_per_period():
    # 2.5 rad/s for 2 s: psi advances 5 rad, which wraps to -1.28.
    a = Landmark(0.0, 2.5, 0.0, 2.0, 0.0)
    b = Landmark(0.0, 2.5, 0.0, 2.0, wrap_angle(5.0))
    assert period_turn(a, b) == pytest.approx(5.0)
    assert period_turn(a._replace(w=0.0), b._replace(w=0.0)) == pytest.approx(wrap_angle(5.0))


def test_modelled_chord_beats_the_mean_heading_on_turn_then_drive():
    # A period starts halfway through a turn in place (1.6 rad/s): 0.8 rad more
    # in 0.5 s, then 1.5 s of driving. The mean of the two psi is 0.4 rad off the
    # chord; the model, turning at the recorded rate where the robot was slow, is not.
    profile = [(0.0, 1.6, 1.0), (0.2, 0.0, 1.5)]
    odom_at, _ = drive(profile)
    a, b = odom_at(0.5), odom_at(2.5)
    start = Landmark(0.0, 1.6, 0.0, 0.5, a.yaw)
    end = Landmark(0.2, 0.0, math.hypot(b.x - a.x, b.y - a.y), 2.0, b.yaw)
    truth = math.atan2(b.y - a.y, b.x - a.x)
    direction = period_shape(start, end, end.d, 16)[0]
    mean = (a.yaw + b.yaw) / 2.0
    assert abs(wrap_angle(mean - truth)) == pytest.approx(0.4, abs=1e-6)
    assert abs(wrap_angle(direction - truth)) < 0.1


class _Counting(list):
    """A list that counts item reads (an iteration or a slice reads every item it yields)."""
    reads = 0

    def __getitem__(self, index):
        value = list.__getitem__(self, index)
        _Counting.reads += len(value) if isinstance(index, slice) else 1
        return value

    def __iter__(self):
        _Counting.reads += len(self)
        return list.__iter__(self)


def test_building_is_linear_in_the_landmark_count():
    calls = []
    original = route_module.period_shape

    def counted(*args):
        calls.append(1)
        return original(*args)
    route_module.period_shape = counted
    try:
        for n in (1000, 4000):
            del calls[:]
            landmarks = [Landmark(0.3, 0.2 * math.sin(k / 7.0), 0.3, 1.0, wrap_angle(k * 0.05))
                         for k in range(n)]
            route = build_route(landmarks, (0.0, 0.0))
            assert len(calls) == n
            assert route.vertices <= (route_module.MAX_SUBDIVISIONS + 1) * n
    finally:
        route_module.period_shape = original


def _count_reads(route):
    """Make every read of the route's geometry lists counted (class attribute)."""
    for name in ('x', 'y', 's', 'speed', 'corner', 'corners'):
        setattr(route, name, _Counting(getattr(route, name)))


def test_following_costs_the_same_per_step_however_long_the_route():
    from blind_navigation.core.route_follower import RouteFollower
    from unicycle import Unicycle
    per_step = []
    for n in (1000, 4000):
        landmarks = [Landmark(0.3, 0.1 * math.sin(k / 9.0), 0.3, 1.0, wrap_angle(0.9 * math.cos(k / 9.0)))
                     for k in range(n)]
        route = build_route(landmarks, (0.0, 0.0))
        follower = RouteFollower(route)
        robot = Unicycle(0.0, 0.0, route.direction(0))
        follower.start(robot.odom)
        _count_reads(route)
        _Counting.reads = 0
        for _ in range(1000):
            v, w = follower.step(robot.odom)
            robot.move(v, w, 0.02)
        assert not follower.failed and follower.section > 5
        per_step.append(_Counting.reads / 1000.0)
    assert per_step[1] < 1.2 * per_step[0], per_step

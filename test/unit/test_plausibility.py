"""Unit tests of core/plausibility.py: the odometry gate (finding 1: a burst of
x = 1e6; finding 2: an impossible twist), the re-anchor rule, the landmark
distance rule and the return's distance budget."""
import math
import random

import pytest

from blind_navigation.core.geometry import OdomState
from blind_navigation.core.landmark import Landmark, landmark_from_values
from blind_navigation.core.plausibility import (KOBUKI_MAX_V, KOBUKI_MAX_W, Limits,
                                                OdometryGate, RouteBudget)
from blind_navigation.core.recorder import PathRecorder
from blind_navigation.sim.kobuki import SENSOR_PERIOD, SimulatedKobuki, load_profile


def kobuki_stream(seed, duration, profile='paper', reset_at=None):
    """Odometry of a simulated Kobuki driven by random commands up to its limits,
    one state per 50 Hz sensor cycle; the odometry is reset at ``reset_at`` s."""
    rng = random.Random(seed)
    base = SimulatedKobuki(load_profile(profile), seed=seed)
    states, command_until = [], 0.0
    while base.t < duration:
        if base.t >= command_until:
            base.command(rng.uniform(-KOBUKI_MAX_V, KOBUKI_MAX_V),
                         rng.uniform(-KOBUKI_MAX_W, KOBUKI_MAX_W))
            command_until = base.t + rng.uniform(0.2, 3.0)
        if reset_at is not None and abs(base.t - reset_at) < 1e-9:
            base.reset_odometry()
        base.step(SENSOR_PERIOD)
        states.append(base.odom)
    return states


@pytest.mark.parametrize('seed, profile', [(1, 'paper'), (2, 'paper'), (3, 'kobuki'), (4, 'ideal')])
def test_a_real_kobuki_stream_is_never_refused(seed, profile):
    gate = OdometryGate()
    states = kobuki_stream(seed, 60.0, profile)
    assert max(abs(s.v) for s in states) > 0.4 and max(abs(s.w) for s in states) > 2.0
    refusals = [gate.check(state) for state in states]
    assert [r for r in refusals if r] == []
    assert gate.refused == 0


def latest_at(states, stamp):
    """The newest of ``states`` (in arrival order) stamped at or before ``stamp``."""
    return max((s for s in states if s.stamp <= stamp), key=lambda s: s.stamp)


@pytest.mark.parametrize('stamped', [True, False])
def test_finding1_a_burst_of_x_1e6_makes_no_landmark_with_a_huge_d(stamped):
    """rostopic pub of /odom at x = 1e6, 100 Hz for 3 s, between the real 50 Hz
    odometry: every bad message refused, every real one accepted, and the
    landmarks recorded from the accepted stream are what the robot did."""
    real = kobuki_stream(5, 20.0)
    burst = [OdomState(1e6, 0.0, 0.0, 0.0, 0.0, (8.0 + i / 100.0) if stamped else 0.0)
             for i in range(300)]
    arrivals = sorted([(s.stamp, 0, s) for s in real]
                      + [(8.0 + i / 100.0 + 1e-4, 1, s) for i, s in enumerate(burst)])
    reanchors = []
    gate = OdometryGate(on_reanchor=reanchors.append)
    accepted = []
    for _, is_burst, state in arrivals:
        problem = gate.check(state)
        assert (problem is not None) == bool(is_burst), (state, problem)
        if problem is None:
            accepted.append(state)
    assert reanchors == [] and gate.refused == 300
    assert accepted == real
    recorder = PathRecorder()
    recorder.start(real[0])
    for tick in range(1, 11):
        odom = latest_at(accepted, 2.0 * tick)
        assert recorder.take(odom, odom.yaw, 2.0).d <= 2.0 * KOBUKI_MAX_V
    # without the gate, the latest message at the tick inside the burst is x = 1e6:
    # the landmark rule refuses it (no landmark with d ~ 1e6) and the chain stays
    unguarded = PathRecorder()
    unguarded.start(real[0])
    for tick in range(1, 5):
        unguarded.take(latest_at(real, 2.0 * tick), 0.0, 2.0)
    newest = [state for arrival, _, state in arrivals if arrival <= 10.005][-1]
    assert newest.x == 1e6
    with pytest.raises(ValueError, match='farther than the base can go'):
        unguarded.take(newest, 0.0, 2.0)
    assert unguarded.count == 4


def test_a_landmark_with_d_1e6_cannot_be_made_nor_loaded():
    with pytest.raises(ValueError, match='d = 1e\\+06 m is farther than the base can go'):
        landmark_from_values([0.1, 0.0, 1e6, 2.0, 0.0])
    recorder = PathRecorder()
    recorder.start(OdomState(0.0, 0.0, 0.0, 0.1, 0.0, 0.0))
    with pytest.raises(ValueError, match='farther'):
        recorder.take(OdomState(1e6, 0.0, 0.0, 0.1, 0.0, 2.0), 0.0, 2.0)
    assert recorder.take(OdomState(0.2, 0.0, 0.0, 0.1, 0.0, 2.0), 0.0, 2.0).d == pytest.approx(0.2)


@pytest.mark.parametrize('v, w, field', [(1e6, 0.0, '|v|'), (0.1, 1e6, '|w|'), (-0.8, 0.0, '|v|'),
                                         (0.1, -3.5, '|w|')])
def test_finding2_impossible_twists_are_refused(v, w, field):
    gate = OdometryGate()
    assert gate.check(OdomState(0.0, 0.0, 0.0, 0.1, 0.0, 0.0)) is None
    problem = gate.check(OdomState(0.002, 0.0, 0.0, v, w, 0.02))
    assert problem and field in problem and 'exceeds the limit' in problem
    assert gate.reference.stamp == 0.0                       # the refused state is not the reference
    assert gate.check(OdomState(0.002, 0.0, 0.0, 0.1, 0.0, 0.02)) is None


@pytest.mark.parametrize('bad, words', [
    (OdomState(float('nan'), 0.0, 0.0, 0.1, 0.0, 1.0), 'x is not a finite'),
    (OdomState(0.0, 0.0, float('inf'), 0.1, 0.0, 1.0), 'yaw is not a finite'),
    (OdomState(0.0, 0.0, 0.0, 0.1, 0.0, float('nan')), 'stamp is not a finite'),
    (OdomState(0.0, 0.0, 0.0, 0.1, 0.0, 0.5), 'stamp went back'),
    (OdomState(0.2, 0.0, 0.0, 0.1, 0.0, 1.02), 'position jumped'),     # 0.2 m in 20 ms
    (OdomState(0.0, 0.0, 0.5, 0.1, 0.0, 1.02), 'yaw jumped'),          # 0.5 rad in 20 ms
])
def test_refused_states_name_the_rule(bad, words):
    gate = OdometryGate()
    assert gate.check(OdomState(0.0, 0.0, 0.0, 0.1, 0.0, 1.0)) is None
    problem = gate.check(bad)
    assert problem and words in problem, problem
    assert gate.refusing and gate.last_refusal == problem


def test_steps_at_the_limits_pass_and_just_beyond_fail():
    gate = OdometryGate({'position_jitter': 0.0, 'yaw_jitter': 0.0, 'speed_margin': 0.0})
    assert gate.check(OdomState(0.0, 0.0, 3.0, 0.7, math.pi, 0.0)) is None
    # a yaw step across +-pi is short: wrap
    assert gate.check(OdomState(0.7 * 0.1, 0.0, 3.0 + math.pi * 0.1 - 2 * math.pi, 0.7, math.pi,
                                0.1)) is None
    assert gate.check(OdomState(0.07 + 0.7 * 0.1 * 1.01, 0.0, -2.97, 0.7, 0.0, 0.2)) is not None


def test_a_genuine_odometry_reset_re_anchors_only_with_a_callback():
    states = kobuki_stream(7, 12.0, reset_at=6.0)
    noted = []
    with_callback = OdometryGate(on_reanchor=noted.append)
    without = OdometryGate()
    refused_with = [s.stamp for s in states if with_callback.check(s)]
    refused_without = [s.stamp for s in states if without.check(s)]
    assert len(noted) == 1 and 'odometry reset?' in noted[0] and with_callback.reanchors == 1
    # refused from the reset until the new stream spanned reanchor_time (1 s)
    assert refused_with[0] == pytest.approx(6.02) and refused_with[-1] == pytest.approx(7.0)
    assert with_callback.reference == states[-1]
    # without a callback the gate holds: everything after the reset is refused
    assert refused_without[0] == pytest.approx(6.02) and refused_without[-1] == states[-1].stamp
    assert without.reanchors == 0


def test_a_garbage_first_state_is_left_behind_by_the_real_stream():
    real = kobuki_stream(8, 4.0)
    noted = []
    gate = OdometryGate(on_reanchor=noted.append)
    assert gate.check(OdomState(1e6, 1e6, 0.0, 0.0, 0.0, 0.0)) is None     # nothing to compare yet
    results = [gate.check(state) for state in real]
    assert len(noted) == 1 and gate.reference == real[-1]
    assert all(r is None for r in results[55:])


@pytest.mark.parametrize('seed', [11, 12])
def test_garbage_never_re_anchors_unless_it_is_the_only_consistent_stream(seed):
    rng = random.Random(seed)
    noted = []
    gate = OdometryGate(on_reanchor=noted.append)
    gate.check(OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    # random garbage, stamps advancing: never self-consistent for 1 s
    for i in range(1, 500):
        assert gate.check(OdomState(rng.uniform(-1e3, 1e3), rng.uniform(-1e3, 1e3),
                                    rng.uniform(-3, 3), 0.0, 0.0, i * 0.01)) is not None
    # constant garbage without a stamp (rostopic pub): consistent, but time does not pass
    for _ in range(500):
        assert gate.check(OdomState(1e6, 0.0, 0.0, 0.0, 0.0, 0.0)) is not None
    assert noted == [] and gate.reference.x == 0.0


def test_landmark_distance_rule_covers_the_final_partial_period_and_rounding():
    limits = Limits()
    # the final landmark: a 10 ms partial period whose odometry states are 20 ms + odom_wait apart
    assert limits.distance_problem(0.7 * 0.03, 0.01) is None
    assert limits.distance_problem(0.7 * 0.01 * 1.1 + 0.7 * 0.25 + 1e-6, 0.01) is not None
    # the fastest honest landmark, stored with six significant digits, still loads
    from blind_navigation.core.store import format_entry
    import yaml
    fastest = Landmark(0.7, 3.14159, 0.7 * (2.0 + 0.25), 2.0, 0.0)
    stored = yaml.safe_load(format_entry('landmark_000001', fastest))['landmark_000001']['data']
    assert landmark_from_values(stored).d == pytest.approx(fastest.d, rel=1e-6)
    # the margins are parameters
    with pytest.raises(ValueError, match='farther'):
        landmark_from_values([0.1, 0.0, 1.5, 2.0, 0.0], Limits(speed_margin=0.0, time_slack=0.0))


def test_the_gates_limits_from_params_refuse_nonsense():
    assert OdometryGate({'max_v': 0.5}).limits.max_v == 0.5
    with pytest.raises(ValueError, match='time_slack'):
        OdometryGate({'time_slack': float('nan')})
    with pytest.raises(ValueError, match='speed_margin'):
        OdometryGate({'speed_margin': -1.0})
    with pytest.raises(ValueError, match='reanchor_time'):
        OdometryGate({'reanchor_time': 0.0})


def test_route_budget():
    path = [Landmark(0.1, 0.0, 0.2, 2.0, 0.0),       # d = v T
            Landmark(0.3, 0.0, 0.2, 2.0, 0.0),       # accelerating: the time mode drives v T = 0.6
            Landmark(0.0, 0.0, 0.15, 2.0, 0.0)]      # stopping: d
    budget = RouteBudget(path)
    assert budget.length == pytest.approx(0.2 + 0.6 + 0.15)
    assert budget.limit == pytest.approx(1.5 * 0.95 + 1.0)
    assert budget.problem(2.0) is None
    problem = budget.problem(97.0)                     # finding 1: 97 m on a 2.3 m route
    assert 'drove 97.00 m' in problem and 'budget of 2.42 m' in problem
    assert 'not a finite' in budget.problem(float('nan'))
    assert RouteBudget(path, {'route_length_factor': 1.0, 'route_length_margin': 0.0}).problem(
        0.96) is not None


def test_a_lone_glitch_before_a_dropout_does_not_hold_the_stream():
    gate = OdometryGate(on_reanchor=lambda reason: pytest.fail(reason))
    assert gate.check(OdomState(0.0, 0.0, 0.0, 0.2, 0.0, 0.0)) is None
    assert gate.check(OdomState(0.3, 0.0, 0.0, 0.2, 0.0, 0.02)) is not None   # glitch
    # the stream was silent for 2 s (the base moved 0.4 m): the glitch is forgotten
    assert gate.check(OdomState(0.4, 0.0, 0.0, 0.2, 0.0, 2.0)) is None
    assert gate.check(OdomState(0.404, 0.0, 0.0, 0.2, 0.0, 2.02)) is None

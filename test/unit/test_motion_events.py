"""Motion events (core/motion_events.py): an event when the robot starts or
stops translating, reverses, or starts or stops turning, dated back to where the
raw speed left the old state (a reversal: where it reads the new direction); none
on steady motion or wheel-ripple noise."""
import math
import random

import pytest

from blind_navigation.core.geometry import OdomState
from blind_navigation.core.motion_events import EventSampler, MotionEvents

DT = 0.02


def events_of(speeds, noise=0.0, seed=0):
    """Event stamps for a 50 Hz series of (v, w)."""
    rng = random.Random(seed)
    detector, found = MotionEvents(), []
    for k, (v, w) in enumerate(speeds):
        stamp = detector.update(OdomState(0, 0, 0, v + rng.gauss(0, noise) if noise else v, w, k * DT))
        if stamp is not None:
            found.append(stamp)
    return found


def lagged(targets, tau=0.25):
    """A first-order lag (the base's momentum) over piecewise targets [(v, w, seconds)]."""
    v = w = 0.0
    out = []
    for tv, tw, seconds in targets:
        for _ in range(int(round(seconds / DT))):
            a = 1.0 - math.exp(-DT / tau)
            v, w = v + (tv - v) * a, w + (tw - w) * a
            out.append((v, w))
    return out


def test_a_reversal_is_dated_at_the_first_state_reading_the_new_direction():
    series = lagged([(0.2, 0.0, 3.0), (-0.2, 0.0, 3.0)])
    found = events_of(series)
    # just after the zero crossing: its sample tells the direction of the period it starts
    crossed = next(k for k, (v, _) in enumerate(series) if v < -0.01) * DT
    assert found[1:] == [pytest.approx(crossed)]


def test_setting_off_stopping_and_turning_in_place_are_events():
    series = lagged([(0.0, 0.0, 1.0), (0.2, 0.0, 3.0), (0.0, 0.0, 2.0), (0.0, 1.0, 3.0), (0.0, 0.0, 2.0)])
    found = events_of(series)
    assert len(found) == 4            # sets off, stops, starts turning, stops turning
    # stopped: where the decaying speed (time constant 0.25 s) fell below event_speed / 2
    assert abs(found[0] - 1.0) < 0.1 and abs(found[1] - (4.0 + 0.25 * math.log(0.2 / 0.005))) < 0.05
    assert abs(found[2] - 6.0) < 0.1


def test_steady_motion_and_ripple_give_no_events():
    assert events_of([(0.0, 0.0)] + [(0.2, 0.05)] * 500) == [DT]     # only setting off
    assert events_of([(0.0, 0.0)] * 500, noise=0.003) == []
    assert len(events_of(lagged([(0.2, 0.0, 10.0)]), noise=0.01)) == 1   # only setting off


def test_a_clock_that_moved_back_starts_the_events_again_with_no_negative_period():
    sampler = EventSampler()
    sampler.start(0.0)
    for k, (v, w) in enumerate(lagged([(0.0, 0.0, 1.0), (0.2, 0.0, 3.0)])):   # sets off at 1 s
        sampler.odometry(OdomState(0, 0, 0, v, w, k * DT))
    state_at = lambda t: OdomState(0, 0, 0, 0.2, 0.0, t)   # noqa: E731
    assert [round(state.stamp, 1) for state, _ in sampler.before(3.5, state_at)] == [1.0]
    assert sampler.tick(3.5, 0.5) == pytest.approx(2.5)     # since the event sample
    # the clock restarts from 0 while the robot drives on, then it stops (time constant 0.25 s)
    assert sampler.tick(0.5, 0.5) == 0.5                     # the tick's own period, not -3.0
    for k in range(100):
        sampler.odometry(OdomState(0, 0, 0, 0.2 * math.exp(-max(0.0, k * DT - 0.5) / 0.25), 0.0,
                                   k * DT))
    taken = sampler.before(2.0, state_at)
    stop = 0.5 + 0.25 * math.log(0.2 / 0.005)               # below event_speed / 2
    assert [round(state.stamp, 1) for state, _ in taken] == [round(stop, 1)]
    assert taken[0][1] == pytest.approx(taken[0][0].stamp - 0.5)    # since the tick at 0.5


def test_the_wheel_ripple_of_a_turn_in_place_makes_no_reversal_event():
    # the paper profile's kinematic base turning in place: v jitters (0.2 s mean: rms 0.008,
    # up to 0.03 m/s); it may read a start or a stop, never forward <-> backward directly
    from blind_navigation.sim.kobuki import SimulatedKobuki, load_profile
    reversals = 0
    for seed in range(5):
        for rate in (0.3, 0.6, 0.9, 1.2):
            base, detector = SimulatedKobuki(load_profile('paper'), seed=seed), MotionEvents()
            for _ in range(int(2 * math.pi / rate / DT)):
                base.command(0.0, rate)
                base.step(DT)
                before = detector.state
                if detector.update(base.odom) is not None:
                    reversals += {before, detector.state} == {'forward', 'backward'}
    assert reversals == 0


def test_a_short_reversal_counts():
    # 0.2 m/s forward, 0.6 s back at 0.1 m/s (about 3 cm), forward again
    found = events_of(lagged([(0.2, 0.0, 2.0), (-0.1, 0.0, 0.6), (0.2, 0.0, 2.0)]))
    assert len(found) == 3            # sets off, reverses, reverses back

"""Allowances that measure progress (core/allowance.ProgressWatch) and the
odometry grace (core/allowance.OdomGrace): a return fails only when it stops
making progress or spends its whole allowance; held time does not count; stale
odometry holds, then continues or aborts after odom_grace, every hold logged."""
from types import SimpleNamespace

import pytest

from blind_navigation.core.allowance import ABORT, DRIVE, HOLD, OdomGrace, ProgressWatch


def watch(nominal=100.0, **params):
    return ProgressWatch(nominal, SimpleNamespace(**params))


def run(progress_watch, start, seconds, along=0.0, speed=0.0, heading=None, step=0.02):
    """Update every ``step`` s; ``along`` grows at ``speed``; returns (t, reason)."""
    t, reason = start, None
    while t < start + seconds - 1e-9 and reason is None:
        t += step
        reason = progress_watch.update(t, along + speed * (t - start), heading)
    return t, reason


def test_no_progress_for_stall_timeout_fails_naming_where():
    w = watch(stall_timeout=4.0)
    t, reason = run(w, 0.0, 3.9)
    assert reason is None
    _, reason = run(w, t, 0.2)
    assert 'no progress for 4.0 s' in reason and '0.00 m' in reason


def test_slow_but_steady_progress_never_stalls():
    w = watch(stall_timeout=4.0, stall_distance=0.005)
    _, reason = run(w, 0.0, 60.0, speed=0.002)       # 5 mm every 2.5 s
    assert reason is None


def test_heading_progress_counts_while_turning_in_place():
    w = watch(stall_timeout=4.0, stall_angle=0.01)
    t = 0.0
    for k in range(300):                              # 6 s turning 0.3 rad/s, not moving
        t += 0.02
        assert w.update(t, 0.0, 3.0 - 0.3 * t) is None
    w.new_heading_goal()
    assert w.update(t + 0.02, 0.0, 1.0) is None       # a new turn starts from its own error


def test_the_whole_return_allowance_is_factor_times_nominal_plus_margin():
    w = watch(nominal=10.0, return_timeout_factor=2.0, return_timeout_margin=5.0)
    assert w.allowance == pytest.approx(25.0)
    t, reason = run(w, 0.0, 24.9, speed=0.1)
    assert reason is None
    _, reason = run(w, t, 0.2, along=2.49, speed=0.1)
    assert 'allowance 25 s spent' in reason


def test_gaps_between_updates_are_held_time_not_counted():
    w = watch(stall_timeout=4.0, max_step_gap=0.5)
    t, _ = run(w, 0.0, 3.0)
    t, reason = run(w, t + 30.0, 0.5)                 # the node held the robot 30 s
    assert reason is None and w.held == pytest.approx(30.02)
    assert w.active == pytest.approx(3.0 + 0.5 - 2 * 0.02)    # the steps that end a gap are held


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match='stall_timeout'):
        watch(stall_timeout=0.0)
    with pytest.raises(ValueError, match='nominal_time'):
        ProgressWatch(float('nan'))


def test_odometry_grace_holds_then_continues_and_logs_the_hold():
    held = []
    grace = OdomGrace(SimpleNamespace(odom_timeout=0.4, odom_grace=3.0), hold=held.append)
    assert grace.check(10.0, 9.9) == (DRIVE, None)
    decision, message = grace.check(10.5, 10.0)
    assert decision == HOLD and 'holding' in message
    assert grace.check(12.0, 10.0) == (HOLD, None)
    decision, message = grace.check(12.5, 12.45)
    assert decision == DRIVE and '2.00 s hold' in message
    assert held == [pytest.approx(2.0)]


def test_odometry_grace_aborts_when_odometry_stays_stale():
    grace = OdomGrace(SimpleNamespace(odom_timeout=0.4, odom_grace=3.0))
    assert grace.check(5.0, None)[0] == HOLD               # none yet
    assert grace.check(7.9, None)[0] == HOLD
    decision, message = grace.check(8.1, None)
    assert decision == ABORT and 'odom_grace 3.0 s' in message

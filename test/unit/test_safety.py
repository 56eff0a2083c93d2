"""Unit tests of core/safety.py: per-goal limits, clamping, Kobuki events,
allowances, the completed landmarks of a route request."""
import math

import pytest

from blind_navigation.core.landmark import Landmark
from blind_navigation.core.safety import (SafetyEvents, VelocityLimits, expected_duration,
                                          goal_limits, landmarks_from_flat, recorded_speed,
                                          return_allowance)


def test_clamp_keeps_curvature_and_limits_both():
    limits = VelocityLimits(0.2, 0.5)
    v, w = limits.clamp(0.4, 0.4)
    assert (v, w) == pytest.approx((0.2, 0.2))
    v, w = limits.clamp(0.1, -1.0)
    assert (v, w) == pytest.approx((0.05, -0.5))
    assert w / v == pytest.approx(-10.0)
    assert limits.clamp(0.1, 0.2) == (0.1, 0.2)
    assert limits.clamp(float('nan'), 0.1) == (0.0, 0.0)
    assert limits.clamp(0.1, float('inf')) == (0.0, 0.0)
    assert VelocityLimits(0.0, 1.0).clamp(0.3, 0.3) == (0.0, 0.0)


def test_goal_never_faster_than_recorded():
    slow = Landmark(0.05, 0.0, 0.12, 2.0, 0.0)          # mean 0.06 m/s > end speed
    assert recorded_speed(slow) == pytest.approx(0.06)
    limits = goal_limits(slow, max_v=0.5, max_w=1.0, correction_w=0.3)
    assert limits.max_v == pytest.approx(0.06)
    assert limits.max_w == pytest.approx(0.3)
    arc = Landmark(0.1, -0.4, 0.1, 1.0, 0.0)
    assert goal_limits(arc, 0.5, 1.0, 0.3) == pytest.approx((0.1, 0.7))
    fast = Landmark(0.6, 0.9, 1.2, 2.0, 0.0)             # configured limits win
    assert goal_limits(fast, 0.5, 1.0, 0.3) == pytest.approx((0.5, 1.0))
    with pytest.raises(ValueError):
        goal_limits(slow, -0.1, 1.0)


def test_safety_events_kobuki_layout():
    events = SafetyEvents()
    assert events.update('bumper', 1, 1) == 'bumper center pressed'
    assert events.active == ['bumper center pressed']
    assert events.update('cliff', 0, 1) == 'cliff left cliff'
    assert events.update('wheel_drop', 1, 1) == 'wheel drop right dropped'
    assert events.update('bumper', 1, 0) is None         # released
    assert events.update('cliff', 0, 0) is None          # floor
    assert events.active == ['wheel drop right dropped']
    assert events.update('wheel_drop', 1, 0) is None     # raised
    assert events.active == []
    assert events.update('bumper', 7, 1) == 'bumper sensor 7 pressed'
    with pytest.raises(ValueError):
        events.update('sonar', 0, 1)


def test_allowances():
    lm = Landmark(0.1, 0.0, 0.3, 2.0, 0.0)
    assert expected_duration(lm) == pytest.approx(3.0)   # d / v > T
    stopped = Landmark(0.0, 0.0, 0.03, 2.0, 0.0)
    assert expected_duration(stopped, slowest_v=0.03) == pytest.approx(2.0)
    assert return_allowance([lm, stopped], 3.0, 30.0) == pytest.approx(3 * 5.0 + 30.0)


def test_landmarks_from_flat():
    values = [0.1, 0.0, 0.2, 2.0, 0.0, 0.1, 0.1, 0.1, 1.0, 0.1]
    assert landmarks_from_flat(values)[1] == Landmark(0.1, 0.1, 0.1, 1.0, 0.1)
    assert landmarks_from_flat([]) == []
    with pytest.raises(ValueError, match='multiple of 5'):
        landmarks_from_flat(values[:7])
    with pytest.raises(ValueError, match='completed landmark 2: d is negative'):
        landmarks_from_flat(values[:5] + [0.1, 0.0, -1.0, 2.0, 0.0])
    with pytest.raises(ValueError, match='not finite'):
        landmarks_from_flat([math.nan, 0.0, 0.1, 1.0, 0.0])

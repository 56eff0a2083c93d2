"""The paper's segment classifier (section 3.3.2) and the two-rate schedule."""
import math
import random

import pytest

from blind_navigation.core.segment import (CURVED, STRAIGHT, SamplingSchedule, classify)
from blind_navigation.core.geometry import wrap_angle


def yaws_along(start, step, count=4):
    """Yaws as the odometry reports them (wrapped to [-pi, pi))."""
    return [wrap_angle(start + i * step) for i in range(count)]


def test_straight_line_is_straight():
    assert classify([0.3, 0.3, 0.3, 0.3]) == STRAIGHT


def test_left_arc_is_curved():
    assert classify(yaws_along(0.0, 0.097)) == CURVED


def test_right_arc_is_curved():
    assert classify(yaws_along(1.0, -0.097)) == CURVED


def test_s_curve_inflection_is_straight_then_each_arc_curved():
    left = yaws_along(0.0, 0.1)
    assert classify(left) == CURVED
    inflection = [0.2, 0.3, 0.2, 0.1]          # turning left, then right
    assert classify(inflection) == STRAIGHT
    right = yaws_along(0.3, -0.1)
    assert classify(right) == CURVED


@pytest.mark.parametrize('step', [0.1, -0.1])
@pytest.mark.parametrize('offset', [0, 1, 2])
def test_turn_across_the_pi_seam_is_curved(step, offset):
    # The yaw jumps by ~2pi once; wherever the jump falls in the window, it is a curve.
    start = math.pi - (offset + 0.5) * abs(step) if step > 0 else -math.pi + (offset + 0.5) * abs(step)
    yaws = yaws_along(start, step)
    diffs = [b - a for a, b in zip(yaws, yaws[1:])]
    assert any(abs(d) > math.pi for d in diffs), yaws
    assert classify(yaws) == CURVED


def test_paper_rule_three_needs_both_signs_and_a_wrap():
    # Both signs but no difference in [pi, 2pi]: a wiggle, straight.
    assert classify([0.0, 0.05, 0.0, 0.05], deadband=0.0) == STRAIGHT
    # Both signs and a wrap-sized difference: curved (rule 3).
    assert classify([3.1, -3.1, -3.05, -3.0], deadband=0.0) == CURVED


def test_deadband_zero_is_the_literal_paper_rule_on_noise():
    tiny_same_sign = [0.0, 0.001, 0.002, 0.003]
    assert classify(tiny_same_sign, deadband=0.0) == CURVED
    assert classify(tiny_same_sign) == STRAIGHT            # default dead-band


def test_straight_heading_at_pi_with_noise_crossing_the_seam_is_straight():
    yaws = [3.1412, -3.1413, 3.1410, -3.1414]
    assert classify(yaws, deadband=0.0) == CURVED           # the paper's literal rule
    assert classify(yaws) == STRAIGHT


def test_default_deadband_keeps_straight_noise_straight():
    rng = random.Random(7)
    curved = 0
    for _ in range(2000):
        yaws = [0.5 + rng.gauss(0.0, 0.002) for _ in range(4)]
        curved += classify(yaws) == CURVED
    assert curved == 0


def test_classify_needs_four_yaws():
    with pytest.raises(ValueError):
        classify([0.0, 0.1, 0.2])


def test_schedule_switches_straight_curve_straight():
    schedule = SamplingSchedule(straight_period=2.0, curved_period=1.0)
    periods = [schedule.update(y) for y in [0.0, 0.0, 0.0, 0.0]]
    assert periods == [2.0, 2.0, 2.0, 2.0]
    periods = [schedule.update(y) for y in [0.1, 0.2, 0.3]]
    assert periods[-1] == 1.0                                # three positive diffs
    periods = [schedule.update(y) for y in [0.3, 0.3, 0.3]]
    assert periods[0] == 2.0 and periods[-1] == 2.0          # the turn has ended


def test_schedule_rejects_bad_periods():
    with pytest.raises(ValueError):
        SamplingSchedule(straight_period=0.0)
    with pytest.raises(ValueError):
        SamplingSchedule(deadband=-1.0)

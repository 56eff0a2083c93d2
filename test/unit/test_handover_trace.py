"""evaluation/handover_trace.py's measures (issue 29): stops, late cycles within goals,
the odometry's drift and the wheel slip of a trace."""
import math

import pytest

from blind_navigation.evaluation import handover_trace as trace
from blind_navigation.sim.kobuki import WHEEL_RADIUS


def test_a_stop_is_a_zero_between_two_moving_commands():
    commands = [(0.0, 0.0), (0.2, 0.0), (0.0, 0.0), (0.0, 0.0), (0.0, 0.3), (0.2, 0.0), (0.0, 0.0)]
    assert trace.stops(commands) == 1          # the zeros before the start and at the end do not count


def test_late_cycles_are_counted_within_goals_not_across_hand_overs():
    commands = [(t, 0.1, 0.0) for t in (0.0, 0.02, 0.04, 0.2, 0.22, 0.24, 0.9, 0.92)]
    # goal 1 from 0 to 0.25 (a 0.16 s late cycle at 0.04-0.2), hand-over to 0.9, goal 2 from 0.9
    assert trace.late_cycles(commands, [0.0, 0.9], [0.25]) == (1, pytest.approx(0.16))


def _row(t, x, y, yaw, v, w, ox, oy, oyaw, left, right, command=(0.2, 0.0)):
    return (t,) + command + (x, y, yaw, v, w, ox, oy, oyaw, v, w, left, right)


def test_the_drift_and_the_slip_of_a_straight_drive():
    # the truth drives 1 m along x in 5 s, the odometry counts 1.02 m; the wheels turn as
    # for 0.204 m/s while the ground moves at 0.2 m/s: 0.004 m/s of slip each
    rim = 0.204 / WHEEL_RADIUS
    rows = [_row(0.1 * k, 0.02 * k, 0.0, 0.0, 0.2, 0.0, 0.0204 * k, 0.0, 0.0, rim, rim) for k in range(51)]
    m = trace.metrics(rows, 0.0)
    assert m['drift_m'] == pytest.approx(0.02)
    assert m['slip_rms'] == pytest.approx(0.004) and m['slip_m'] == pytest.approx(2 * 0.004 * 5.0)
    assert m['length'] == pytest.approx(1.0) and m['odom_length'] == pytest.approx(1.02)
    assert m['cmd_minus_v_rms'] == pytest.approx(0.0, abs=1e-9) and m['stops'] == 0


def test_the_drift_is_measured_in_the_truth_frame_at_the_start():
    # the odometry's frame is turned 90 degrees from the truth's: the same motion, no drift
    rows = [_row(0.1 * k, 0.02 * k, 0.0, 0.0, 0.2, 0.0, 0.0, 0.02 * k, math.pi / 2, 0.0, 0.0)
            for k in range(11)]
    assert trace.metrics(rows, 0.0)['drift_m'] == pytest.approx(0.0, abs=1e-12)

"""Unit tests of the simulated Kobuki: geometry, determinism, command timeout, limits, sensors."""
import math

import pytest

from blind_navigation.sim.arena import Arena
from blind_navigation.core.geometry import Pose2D
from blind_navigation.sim.kobuki import (CMD_TIMEOUT, MAX_V, SimulatedKobuki, arc_motion,
                                          load_profile, make_profile)


def drive(base, v, w, seconds, rate=10.0):
    """Send (v, w) at ``rate`` Hz for ``seconds``, stepping the base in between."""
    for _ in range(int(round(seconds * rate))):
        base.command(v, w)
        base.step(1.0 / rate)


def test_ideal_straight_line_ends_where_geometry_says():
    base = SimulatedKobuki(load_profile('ideal'))
    drive(base, 0.2, 0.0, 10.0)
    drive(base, 0.0, 0.0, 1.0)        # the operator stops
    assert base.true_pose.x == pytest.approx(2.0, rel=0.01)
    assert base.odom.x == pytest.approx(2.0, rel=0.01)
    assert abs(base.true_pose.y) < 1e-9


def test_ideal_arc_ends_where_geometry_says():
    base = SimulatedKobuki(load_profile('ideal'))
    v, w, seconds = 0.1, 0.5, 2.0 * math.pi / 0.5 / 4.0      # a quarter circle of radius 0.2 m
    drive(base, v, w, seconds, rate=50.0)
    radius = v / w
    assert base.true_pose.x == pytest.approx(radius, rel=0.01)
    assert base.true_pose.y == pytest.approx(radius, rel=0.01)
    assert base.true_pose.yaw == pytest.approx(math.pi / 2.0, rel=0.01)
    assert base.odom.yaw == pytest.approx(math.pi / 2.0, rel=0.01)


def test_ideal_base_is_an_exact_unicycle():
    # an arc of about a quarter circle ends exactly where the closed form says (the
    # midpoint rule this replaced missed it by ~3e-7 m), a near-straight one too
    base = SimulatedKobuki(load_profile('ideal'), start=Pose2D(1.0, -2.0, 0.3))
    v, w, seconds = 0.1, 0.5, 3.14
    drive(base, v, w, seconds, rate=50.0)
    radius, end = v / w, 0.3 + w * seconds
    assert base.true_pose.x == pytest.approx(1.0 + radius * (math.sin(end) - math.sin(0.3)), abs=1e-9)
    assert base.true_pose.y == pytest.approx(-2.0 - radius * (math.cos(end) - math.cos(0.3)), abs=1e-9)
    assert base.true_pose.yaw == pytest.approx(end, abs=1e-9)
    assert arc_motion(0.0, 0.0, 0.0, 0.2, 1e-9, 3.0) == pytest.approx((0.6, 9e-10, 3e-9), abs=1e-15)


def test_a_placed_base_moves_on_from_where_it_was_put_and_its_sensors_do_not_count_the_carry():
    base = SimulatedKobuki(load_profile('ideal'))
    base.place(Pose2D(2.0, 1.0, math.pi / 2.0))
    drive(base, 0.2, 0.0, 1.0)
    assert base.true_pose.x == pytest.approx(2.0, abs=1e-9)
    assert base.true_pose.y == pytest.approx(1.0 + 0.2 * 1.0, abs=1e-9)
    assert base.odom.yaw == pytest.approx(0.0, abs=1e-9)      # the gyro did not see the carry
    assert base.odom.x == pytest.approx(0.2, abs=1e-3)


def test_same_seed_same_trajectory_other_seed_other_trajectory():
    def run(seed):
        base = SimulatedKobuki(load_profile('paper'), seed=seed)
        poses = []
        for _ in range(20):
            drive(base, 0.1, 0.05, 0.5)
            poses.append((base.true_pose, base.odom))
        return poses
    assert run(7) == run(7)
    assert run(7) != run(8)


def test_command_times_out_after_0_6_s_checked_at_10_hz():
    base = SimulatedKobuki(load_profile('ideal'))
    base.command(0.2, 0.0)
    base.step(0.6)
    assert base.command_active and base.true_twist[0] == pytest.approx(0.2)
    base.step(0.11)                   # the 10 Hz check at t = 0.7 s drops it
    assert not base.command_active
    assert base.true_twist == (0.0, 0.0)
    stopped_at = base.true_pose.x
    base.step(2.0)
    assert base.true_pose.x == stopped_at
    assert stopped_at == pytest.approx(0.2 * (CMD_TIMEOUT + 0.1), abs=1e-6)


def test_commands_are_clamped_and_non_finite_rejected():
    base = SimulatedKobuki(load_profile('ideal'))
    base.command(5.0, -10.0)
    base.step(0.1)
    assert base.true_twist[0] == pytest.approx(MAX_V)
    assert base.true_twist[1] == pytest.approx(-math.pi)
    with pytest.raises(ValueError, match='finite'):
        base.command(float('nan'), 0.0)


def test_acceleration_limiter_ramps_at_kobuki_rates():
    base = SimulatedKobuki(make_profile({'acceleration_limiter': True}))
    drive(base, 0.5, 0.0, 0.5)
    assert base.true_twist[0] == pytest.approx(0.25, abs=0.011)    # +0.5 m/s^2
    drive(base, 0.5, 0.0, 0.5)
    drive(base, 0.0, 0.0, 0.5)
    assert base.true_twist[0] == pytest.approx(0.5 - 0.3, abs=0.011)  # -0.6 m/s^2


def test_motor_lag_makes_the_robot_fall_short_at_start():
    base = SimulatedKobuki(make_profile({'motor_time_constant': 0.2}))
    drive(base, 0.1, 0.0, 1.0)
    assert 0.1 - 0.1 * 0.2 * 1.2 < base.true_pose.x < 0.1 - 0.1 * 0.2 * 0.8


def test_motor_power_off_stops_and_reset_odometry_zeroes():
    base = SimulatedKobuki(load_profile('ideal'))
    drive(base, 0.2, 0.3, 2.0)
    base.set_motor_power(False)
    base.command(0.2, 0.0)
    here = base.true_pose
    base.step(0.5)
    assert base.true_pose == here
    base.reset_odometry()
    base.step(0.02)
    assert (base.odom.x, base.odom.y, base.odom.yaw) == (0.0, 0.0, 0.0)


def test_gyro_bias_makes_the_heading_drift_while_standing():
    base = SimulatedKobuki(make_profile({'gyro_bias_max': 5.8e-4}), seed=3)
    base.step(100.0)
    assert base.true_pose.yaw == 0.0
    assert 0.0 < abs(base.odom.yaw) <= 5.8e-4 * 100.0 + 1e-9


def test_unequal_wheels_curve_a_straight_command():
    base = SimulatedKobuki(make_profile({'wheel_diameter_ratio': 1.01}))
    drive(base, 0.2, 0.0, 10.0)
    assert base.true_pose.yaw > 0.01          # right wheel larger: turns left
    assert abs(base.odom.yaw) < 1e-9 or base.odom.yaw > 0.0


def test_wall_blocks_and_presses_the_center_bumper():
    base = SimulatedKobuki(load_profile('ideal'), arena=Arena((-1.0, 1.0, -1.0, 1.0)))
    drive(base, 0.3, 0.0, 6.0)
    assert base.true_pose.x == pytest.approx(1.0 - 0.177, abs=0.01)
    assert base.contacts.bumper == {'center'}
    assert base.odom.x > 1.5                  # wheels slip on, odometry runs away


def test_cliff_edge_raises_cliff_then_drops_the_wheels():
    base = SimulatedKobuki(load_profile('ideal'), arena=Arena((-1.0, 1.0, -1.0, 1.0), edge='cliff'),
                           start=Pose2D(0.0, 0.0, 0.0))
    seen_cliff = False
    for _ in range(100):
        drive(base, 0.2, 0.0, 0.1)
        seen_cliff = seen_cliff or base.contacts.cliff == {'left', 'center', 'right'}
    assert seen_cliff
    assert base.contacts.wheel_drop == {'left', 'right'} and base.fallen


def test_bad_profiles_are_rejected_with_names():
    with pytest.raises(ValueError, match='unknown noise parameter .gyro_bias.'):
        make_profile({'gyro_bias': 1.0})
    with pytest.raises(ValueError, match='ripple_std must be a finite number'):
        make_profile({'ripple_std': 'x'})
    with pytest.raises(ValueError, match="noise profile 'nope' not found"):
        load_profile('nope')
    with pytest.raises(ValueError, match='multiple of physics_dt'):
        SimulatedKobuki(load_profile('ideal')).step(0.015)

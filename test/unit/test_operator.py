"""Unit tests of the teleoperator model (core/operator.py) and its use by missions and the harness."""
import math

import pytest

from blind_navigation.core.geometry import Pose2D
from blind_navigation.sim.kobuki import SimulatedKobuki, load_profile
from blind_navigation.sim.mission import load_mission, mission_from_dict
from blind_navigation.sim.operator import Operator, ReferencePath, operator_params

STRAIGHT = {'segments': [{'v': 0.1, 'distance': 3.0}], 'operator': {'max_w': 0.1}}


def drive(mission, profile, seed=0, dt=0.02):
    """Operator + simulated base at the mission's teleop rate; returns (base, commands, duration)."""
    base = SimulatedKobuki(profile, seed=seed)
    operator = mission.make_operator()
    operator.start(base.true_pose)
    every = int(round(1.0 / (mission.rate * dt)))
    commands, k = [], 0
    while True:
        if k % every == 0:
            command = operator.command(k * dt)
            if command is None:
                break
            commands.append(command)
            base.command(*command)
        base.step(dt)
        k += 1
        operator.observe(k * dt, base.true_pose)
    return base, commands, k * dt


def test_reference_path_lays_arcs_end_to_end():
    path = ReferencePath([(0.1, 0.0, 10.0), (0.1, 0.1, math.pi / 2 / 0.1)])
    assert path.length == pytest.approx(1.0 + math.pi / 2, abs=1e-6)
    x, y = path.point_at(path.length)
    assert (x, y) == pytest.approx((2.0, 1.0), abs=1e-3)     # quarter circle of radius 1 m
    s, lateral = path.locate(0.5, 0.2)
    assert s == pytest.approx(0.5, abs=0.01) and lateral == pytest.approx(0.2, abs=1e-6)


def test_person_keeps_a_drifting_robot_on_the_line_by_tapping_the_turn_key():
    # 2 % wheel-diameter mismatch: the open-loop script ends ~0.4 m off.
    profile = dict(load_profile('ideal'), wheel_diameter_ratio=1.02)
    mission = mission_from_dict(STRAIGHT)
    base, commands, _ = drive(mission, profile)
    assert abs(base.true_pose.y) < 0.1 and base.true_pose.x == pytest.approx(3.0, abs=0.05)
    turns = {w for _, w in commands}
    assert turns <= {0.0, 0.1, -0.1} and -0.1 in turns      # keyboard: -ASV, 0, +ASV only
    assert all(v == 0.1 for v, _ in commands)
    open_loop = SimulatedKobuki(profile)
    for _ in range(300):
        open_loop.command(0.1, 0.0)
        open_loop.step(0.1)
    assert abs(open_loop.true_pose.y) > 0.3


def test_taps_last_error_over_asv_in_teleop_periods_then_wait():
    mission = mission_from_dict(dict(STRAIGHT, operator={'max_w': 0.1, 'reaction_time': 0.0}))
    operator = Operator(mission, mission.operator)
    operator.start(Pose2D(0.0, 0.0, 0.0))
    operator.observe(0.0, Pose2D(0.0, 0.0, -0.05))            # 0.05 rad off to the right
    taps = [operator.command(0.1 * k)[1] for k in range(12)]
    assert taps[:5] == [0.1] * 5                              # 0.05 rad / 0.1 rad/s = 0.5 s
    assert taps[5:10] == [0.0] * 5                            # refractory 0.5 s
    assert taps[10] == 0.1                                    # still seen off: tap again
    operator.observe(1.7, Pose2D(0.17, 0.0, 0.0))
    assert operator.command(2.2)[1] == 0.0                    # aligned: no tap


def test_reaction_time_delays_what_the_person_sees():
    mission = mission_from_dict(dict(STRAIGHT, operator={'max_w': 0.1, 'reaction_time': 0.3}))
    operator = mission.make_operator()
    operator.start(Pose2D(0.0, 0.0, 0.0))
    operator.observe(0.1, Pose2D(0.01, 0.0, 0.3))
    assert operator.command(0.1)[1] == 0.0                    # the turn is not seen yet
    operator.observe(0.4, Pose2D(0.04, 0.0, 0.3))
    assert operator.command(0.4)[1] < 0.0


def test_same_seed_same_run_and_the_route_ends_the_mission():
    mission = load_mission('table6_test1')
    paper = load_profile('paper')
    first, second = drive(mission, paper, seed=3), drive(mission, paper, seed=3)
    assert first[1] == second[1]
    assert first[0].true_pose == second[0].true_pose
    assert first[2] < mission.operator['allowance_factor'] * mission.duration


def test_bad_operator_parameters_are_named():
    with pytest.raises(ValueError, match='reaction'):
        operator_params({'reaction': 0.3})
    with pytest.raises(ValueError, match='preview'):
        operator_params({'preview': -1})
    with pytest.raises(ValueError, match='turn rate'):
        mission_from_dict({'segments': [{'v': 0.1, 'distance': 1.0}], 'operator': True}).make_operator()
    with pytest.raises(ValueError, match=r'segments \[1\] reverse'):
        mission_from_dict({'segments': [{'v': 0.1, 'distance': 1.0}, {'v': -0.1, 'distance': 0.5}],
                           'operator': {'max_w': 0.1}}).make_operator()


def test_operator_is_opt_in_per_mission_file():
    assert mission_from_dict({'segments': [{'v': 0.1, 'distance': 1.0}]}).make_operator() is None
    assert load_mission('table6_test6').make_operator() is not None


def test_common_ripple_changes_speed_not_heading():
    profile = dict(load_profile('ideal'), ripple_std=0.014, ripple_knee=0.2, ripple_time=0.4)
    headings = {}
    for common in (0.0, 1.0):
        base = SimulatedKobuki(dict(profile, ripple_common=common), seed=1)
        speeds = []
        for _ in range(300):
            base.command(0.086, 0.0)
            base.step(0.1)
            speeds.append(base.true_twist[0])
        headings[common] = abs(base.true_pose.yaw)
        assert max(speeds[10:]) - min(speeds[10:]) > 0.005
    assert headings[1.0] < 1e-9 < headings[0.0]

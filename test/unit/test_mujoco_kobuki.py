"""The physics base (sim/mujoco_kobuki.py): the Kobuki on MuJoCo behind SimulatedKobuki's interface."""
import copy
import math

import pytest

from blind_navigation.sim.harness import run_mission
from blind_navigation.sim.kobuki import TICKS_PER_REV, load_profile
from blind_navigation.sim.mujoco_kobuki import engine_name, import_mujoco, load_world, make_base

try:
    import_mujoco()
except ImportError as error:           # make deps installs it (scripts/install_deps.sh: requirements/sim.txt)
    pytest.skip('mujoco not installed: %s' % error, allow_module_level=True)


def drive(base, v, w, seconds):
    """Command (v, w) at 50 Hz for ``seconds`` s of sim time."""
    for _ in range(int(round(seconds / 0.02))):
        base.command(v, w)
        base.step(0.02)


def test_engine_is_named_with_its_version():
    assert engine_name().startswith('MuJoCo 3.')


def test_straight_drive_is_physical_not_exact():
    base = make_base('mujoco', load_profile('ideal'), world='tile')
    drive(base, 0.3, 0.0, 5.0)
    base.step(2.0)                       # the 0.6 s timeout, then the limiter stops it
    truth, odom = base.true_pose, base.odom
    assert 1.4 < truth.x < 1.8, truth
    assert abs(truth.y) < 1e-3 and abs(truth.yaw) < 1e-3, truth
    slip = odom.x / truth.x - 1.0
    assert 0.0 < slip < 0.02, 'the wheels slip a little on tile: %.4f' % slip


def test_speed_limit_and_acceleration_limiter():
    base = make_base('mujoco', load_profile('ideal'))
    drive(base, 2.0, 0.0, 0.4)
    assert base.true_twist[0] <= 0.5 * 0.4 + 0.02, 'kobuki_node accelerates at 0.5 m/s^2: %r' % (base.true_twist,)
    drive(base, 2.0, 0.0, 3.0)
    assert 0.65 < base.true_twist[0] <= 0.7 + 0.01, 'clamped to 0.7 m/s: %r' % (base.true_twist,)


def test_command_times_out_after_0_6_s():
    base = make_base('mujoco', load_profile('ideal'))
    drive(base, 0.2, 0.0, 1.0)
    base.step(0.7)                       # checked at 10 Hz: dropped within 0.7 s
    assert base.command_active is False
    base.step(1.0)
    assert abs(base.true_twist[0]) < 0.005, 'stopped: %r' % (base.true_twist,)


def test_encoders_are_quantised_wheel_joint_angles():
    base = make_base('mujoco', load_profile('ideal'))
    drive(base, 0.2, 0.5, 1.0)
    for angle in base.wheel_angles:
        ticks = angle / (2.0 * math.pi) * TICKS_PER_REV
        assert abs(ticks - round(ticks)) < 1e-6, ticks
    assert base.wheel_angles[1] > base.wheel_angles[0] > 0.0, 'turning left: right wheel ahead'


def test_gyro_scale_error_from_the_profile():
    profile = load_profile('ideal')
    profile['gyro_scale_error'] = 0.01
    base = make_base('mujoco', profile)
    drive(base, 0.0, 1.0, 3.0)
    base.step(1.0)
    assert abs(base.gyro_heading / base.true_pose.yaw - 1.01) < 0.002, (base.gyro_heading, base.true_pose.yaw)


def test_same_seed_same_run_and_a_copy_goes_on_alike():
    runs = []
    for _ in range(2):
        base = make_base('mujoco', load_profile('paper'), seed=3)
        drive(base, 0.25, 0.3, 2.0)
        runs.append(base)
    assert runs[0].true_pose == runs[1].true_pose and runs[0].odom == runs[1].odom
    twin = copy.deepcopy(runs[0])
    drive(runs[0], 0.2, -0.4, 1.0)
    drive(twin, 0.2, -0.4, 1.0)
    assert twin.true_pose == runs[0].true_pose


@pytest.mark.parametrize('world', ['threshold', 'ramp'])
def test_crosses_the_threshold_and_the_ramp(world):
    flat = make_base('mujoco', load_profile('ideal'), world='tile')
    base = make_base('mujoco', load_profile('ideal'), world=world)
    for robot in (flat, base):
        drive(robot, 0.3, 0.0, 8.0)
    assert base.true_pose.x > 2.0, 'crossed it: %r' % (base.true_pose,)
    assert base.true_pose.x < flat.true_pose.x, 'it costs some travel: %r vs %r' % (base.true_pose, flat.true_pose)


def test_carpet_slips_more_than_tile():
    slips = {}
    for world in ('tile', 'carpet'):
        base = make_base('mujoco', load_profile('ideal'), world=world)
        drive(base, 0.0, 1.5, 4.0)
        base.step(1.0)
        wheel_turn = (base.wheel_angles[1] - base.wheel_angles[0]) * 0.035 / 0.230
        slips[world] = wheel_turn / base.true_pose.yaw - 1.0
    assert 0.0 < slips['tile'] < slips['carpet'], slips


def test_payload_off_centre_pulls_a_straight_drive_aside():
    """2 kg 5 cm left or right of the axle's middle: the body rolls onto one wheel and the
    straight drive curves, mirrored; centred, it stays straight."""
    yaws = {}
    for y in (0.0, 0.05, -0.05):
        base = make_base('mujoco', load_profile('ideal'), payload=(2.0, 0.0, y))
        assert abs(base.model.body_subtreemass[1] - 4.35) < 1e-6
        drive(base, 0.3, 0.0, 4.0)
        yaws[y] = base.true_pose.yaw
    assert abs(yaws[0.0]) < 1e-3, yaws
    assert abs(yaws[0.05]) > 0.02 and abs(yaws[0.05] + yaws[-0.05]) < 1e-3, yaws


def test_bad_worlds_and_bases_are_refused():
    with pytest.raises(ValueError, match='not found'):
        load_world('no_such_world')
    with pytest.raises(ValueError, match='unknown base'):
        make_base('gazebo', load_profile('ideal'))
    with pytest.raises(ValueError, match='no arena'):
        make_base('mujoco', load_profile('ideal'), arena=object())


def test_a_mission_on_the_physics_base_comes_home():
    result = run_mission('table6_test1', 'paper', 'closed_loop', seed=0, base='mujoco', floor=False)
    assert result.status == 'home', result.reason
    assert result.position_error < 0.02 * result.distance, (result.position_error, result.distance)

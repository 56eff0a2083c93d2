"""The fake's auto-docking (sim/dock_drive.py, sim/docking.py): kobuki_dock_drive's state
machine cycle by cycle, and whole goals on the kinematic and the MuJoCo base from seeded
starts in the dock's field (success rate, time), from 1.5 m aside and from behind (fail
without wandering), askew of the axis near the dock (dock, or abort after the bump's retry)."""
import math
import random

import pytest

from blind_navigation.core.geometry import Pose2D
from blind_navigation.sim import dock as d
from blind_navigation.sim.dock_drive import DOCK_STABILIZER, DockDrive
from blind_navigation.sim.docking import BUMP_LIMIT, LOST_TIME, SUCCEEDED, TIME_LIMIT, run_docking, verdict
from blind_navigation.sim.kobuki import load_profile
from blind_navigation.sim.mujoco_kobuki import import_mujoco, make_base

CENTRE = [0, d.NEAR_CENTER | d.FAR_CENTER, 0]
NOTHING = [0, 0, 0]
DOCK = d.Dock(Pose2D(0.0, 0.0, 0.0))


def mujoco_available():
    try:
        import_mujoco()
        return True
    except ImportError:
        return False


BASES = ['kinematic', pytest.param('mujoco', marks=pytest.mark.skipif(not mujoco_available(),
                                                                      reason='mujoco not installed'))]


def test_scan_turns_until_the_central_receiver_sees_the_central_beam():
    drive = DockDrive()
    assert drive.update(NOTHING, 0, 0, 0.0) == (0.0, 0.66) and drive.state == 'SCAN'
    assert drive.update(NOTHING, 0, 0, 0.01) == (0.0, 0.66)
    assert drive.update(CENTRE, 0, 0, 0.02) == (0.05, 0.0) and drive.state == 'ALIGNED'
    assert drive.update(CENTRE, 0, 0, 0.02) == (0.05, 0.0) and drive.state == 'ALIGNED_NEAR'


def test_aligned_far_steers_back_to_the_centre():
    drive = DockDrive()
    drive.update(NOTHING, 0, 0, 0.0)
    drive.update([0, d.FAR_CENTER, 0], 0, 0, 0.0)
    assert drive.update([0, d.FAR_CENTER, 0], 0, 0, 0.0) == (0.1, 0.0) and drive.state == 'ALIGNED_FAR'
    drive = DockDrive()
    drive.update(NOTHING, 0, 0, 0.0)
    drive.update([0, d.FAR_CENTER, 0], 0, 0, 0.0)
    for _ in range(25):                                   # past the 20-cycle window of the centre
        v, w = drive.update([0, d.FAR_LEFT, 0], 0, 0, 0.0)
    assert (v, w, drive.state) == (0.1, 0.3, 'ALIGNED_FAR')   # on the dock's left: turn ccw


def test_a_full_turn_without_the_dock_ends_in_unknown_standing_still():
    drive, heading = DockDrive(), 0.0
    for _ in range(int(2 * math.pi / (0.66 * 0.02)) + 5):
        v, w = drive.update(NOTHING, 0, 0, heading)
        heading += w * 0.02
    for _ in range(3):
        v, w = drive.update(NOTHING, 0, 0, heading)
    assert drive.state == 'UNKNOWN' and (v, w) == (0.0, 0.0)
    assert verdict(drive, 10.0)[0] is False and 'dock not seen' in verdict(drive, 10.0)[1]


def test_the_charger_docks_in_then_done_and_a_bump_backs_off():
    drive = DockDrive()
    assert drive.update(CENTRE, d.BUMPER_CENTRE, 0, 0.0) == (-0.05, 0.0) and drive.state == 'BUMPED'
    for _ in range(DOCK_STABILIZER):
        assert drive.update(CENTRE, 0, d.CHARGING, 0.0) == (0.0, 0.0) and drive.state == 'DOCKED_IN'
    drive.update(CENTRE, 0, d.CHARGING, 0.0)
    assert drive.done and verdict(drive, 1.0) == (True, SUCCEEDED)


def test_a_second_bump_ends_the_goal_once_backed_off():
    drive, bumps = DockDrive(), []
    drive.update(CENTRE, 0, 0, 0.0)
    for _ in range(BUMP_LIMIT):
        while drive.state != 'ALIGNED_NEAR':                  # the published retry: back off, re-align
            assert verdict(drive, 1.0) is None
            drive.update(CENTRE, 0, 0, 0.0)
        bumps.append([drive.update(CENTRE, d.BUMPER_CENTRE, 0, 0.0) for _ in range(3)])
        assert verdict(drive, 1.0) is None and drive.bumped == len(bumps)   # not ended pressed on it
    assert bumps == [[(-0.05, 0.0)] * 3] * BUMP_LIMIT
    while drive.state.startswith('BUMPED'):
        assert verdict(drive, 1.0) is None
        v, w = drive.update(CENTRE, 0, 0, 0.0)
    assert (drive.state, v, w) == ('SCAN', 0.0, 0.0)
    assert verdict(drive, 1.0) == (False, 'Aborted: bumped %d times without charging, backed off '
                                          '(state SCAN).' % BUMP_LIMIT)


def test_the_time_limit_and_a_lost_dock_end_a_goal():
    drive = DockDrive()
    drive.update(CENTRE, 0, 0, 0.0)
    assert verdict(drive, 1.0) is None
    assert 'time limit' in verdict(drive, TIME_LIMIT + 0.1)[1]
    # on the dock's left (the central receiver sees the left beam while scanning), a full turn,
    # then the right receiver finds the left beam: GET_STREAM drives for the central line...
    drive, heading, left_beam = DockDrive(), 0.0, [0, d.FAR_LEFT, 0]
    while drive.state != 'FIND_STREAM':
        heading += drive.update(left_beam if heading < 0.5 else NOTHING, 0, 0, heading)[1] * 0.02
    drive.update([d.FAR_LEFT, 0, 0], 0, 0, heading)
    assert drive.state == 'GET_STREAM'
    # ... and no beam comes any more: it drives on, until the fake gives up
    while verdict(drive, 10.0) is None:
        assert drive.update(NOTHING, 0, 0, heading) == (0.05, 0.0) and drive.unseen_time <= LOST_TIME + 0.03
    assert 'dock lost' in verdict(drive, 10.0)[1]


def starts(count, seed=1):
    """Seeded starts in the dock's near field: 0.4-2.5 m ahead, up to 0.8 m aside, any heading."""
    rng = random.Random(seed)
    return [Pose2D(rng.uniform(0.4, 2.5), rng.uniform(-0.8, 0.8), rng.uniform(-math.pi, math.pi))
            for _ in range(count)]


def dock_from(base_name, start, seed):
    base = make_base(base_name, load_profile('paper'), seed=seed)
    base.place(start)
    return base, run_docking(base, DOCK)


@pytest.mark.parametrize('base_name, count, rate', [('kinematic', 30, 0.9), ('mujoco', 12, 0.75)],
                         ids=['kinematic', 'mujoco'])
def test_seeded_starts_near_the_dock_mostly_dock(base_name, count, rate):
    if base_name == 'mujoco' and not mujoco_available():
        pytest.skip('mujoco not installed')
    results = [dock_from(base_name, start, seed)[1] for seed, start in enumerate(starts(count))]
    docked = [r for r in results if r.docked]
    assert len(docked) >= rate * count, [(r.state, r.text) for r in results if not r.docked]
    times = sorted(r.time for r in docked)
    assert times[len(times) // 2] < 90.0 and max(r.farthest for r in results) < 3.0
    for result in results:
        assert result.docked == (result.state == 'DONE')


@pytest.mark.parametrize('base_name', BASES)
@pytest.mark.parametrize('start', [Pose2D(0.3, 1.5, math.pi), Pose2D(-0.5, 0.0, 0.0), Pose2D(-1.0, 0.3, 1.0)],
                         ids=['1.5 m aside', 'behind', 'behind aside'])
def test_out_of_the_field_it_fails_without_wandering(base_name, start):
    base, result = dock_from(base_name, start, seed=3)
    assert not result.docked and result.state == 'UNKNOWN' and 'dock not seen' in result.text
    assert result.farthest < 0.05 and result.time < 15.0          # one turn on the spot, then still
    assert base.true_twist[0] == pytest.approx(0.0, abs=0.02)


@pytest.mark.parametrize('base_name', BASES)
@pytest.mark.parametrize('off', [25.0, -25.0], ids=['25 deg left', '25 deg right'])
def test_askew_of_the_axis_near_the_dock_it_docks_or_aborts_after_the_retry(base_name, off):
    """0.3 m before the dock's face on a line ``off`` degrees off its axis, facing the dock: the
    drive noses in beyond the contacts' 20 degrees, bumps, backs off 1 cm and re-aligns on the
    same beam; the fake docks or gives up at the next bump, backed off, long before its limit."""
    a = math.radians(off)
    base, result = dock_from(base_name, Pose2D(0.3 * math.cos(a), 0.3 * math.sin(a), math.pi + a), seed=3)
    assert result.docked or 'bumped %d times' % BUMP_LIMIT in result.text, result
    assert result.time < TIME_LIMIT / 4 and result.farthest < 0.3, result
    for _ in range(50):                                   # 1 s with no new command: it stands
        base.step(0.02)
    contact = DOCK.contact(base.true_pose)
    assert contact.docked == result.docked and contact.bumper == 0
    assert base.true_twist[0] == pytest.approx(0.0, abs=0.005)

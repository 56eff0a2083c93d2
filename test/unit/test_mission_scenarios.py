"""Behaviour scenarios of the mission rostests played by the harness on the same
core/mission.Mission (issue 30 item 7): the same mission files, noise profiles, modes and
limits as each rostest (named in each test's docstring), seeded, on the simulated robot's
ground truth. blind_navigation.launch's defaults (mission_rig.launch): heading_correction,
prune_loops (closed_loop), vision_back_grace 5 s."""
import math
import os

import pytest

from blind_navigation.core import outcome
from blind_navigation.core.allowance import ALLOWANCE_DEFAULTS, OdomGrace
from blind_navigation.core.gyro_calibration import load_calibration
from blind_navigation.sim.harness import play
from blind_navigation.sim.kobuki import load_profile
from blind_navigation.sim.mujoco_kobuki import import_mujoco
from test_mission_harness import _ended_at, _speed, _states, _still_after
from test_mission_harness_limits import _entered

CALIBRATION = load_calibration(os.path.join(os.path.dirname(__file__), '..', 'rostest',
                                            'fake_paper_gyro_calibration.yaml'))
#: blind_navigation.launch's settings the rostests run with (closed_loop)
LAUNCH = dict(prune_loops=True, vision_back_grace=5.0, floor=False)
HOME = ['idle', 'recording', 'rotating', 'returning', 'home']


def _length(path):
    return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(path, path[1:]))


def _home_within(played, limit):
    """Home, states walked in order, within ``limit`` m of the start (ground truth), still."""
    result = played.result
    assert result.status == 'home', result.reason
    assert _states(played) == HOME and played.mission.machine.outcome == outcome.HOME
    assert result.position_error <= limit, '%.3f m > %.3f m' % (result.position_error, limit)
    assert _speed(played) < 1e-3


def _home_within_share(played, share):
    """test_mission_real_paths's outcome: the operator drove >= 90 % of the recorded path; home
    within ``share`` of the path driven while recording (ground truth), still."""
    forward = _length(played.result.forward_path)
    assert forward > 0.9 * played.result.distance
    _home_within(played, share * forward)


# --- closed_loop on arcs (test_mission.py, ideal profile, limit 0.075 m) -------------------
@pytest.mark.parametrize('mission', ['test_left_arc', 'test_right_arc', 'test_s_curve'])
def test_arcs_come_home_closed_loop(mission):
    """Replaces mission_left_arc_closed_loop, mission_right_arc_closed_loop and
    mission_s_curve_closed_loop: a mirrored arc ends metres away, the limit is 0.075 m."""
    played = play(mission, 'ideal', 'closed_loop', 0, **LAUNCH)
    _home_within(played, 0.075)
    assert _length(played.result.forward_path) > 0.9 * played.result.distance


# --- time mode on arcs (test_mission.py, ideal profile, limit 30 % of the path) ------------
@pytest.mark.parametrize('mission, limit', [('test_right_arc', 0.59), ('test_s_curve', 1.06)])
def test_arcs_come_home_in_time_mode(mission, limit):
    """Replaces mission_right_arc_time and mission_s_curve_time (lane_mission_left_arc_time.test
    keeps the left arc over ROS, the paper's layout): the paper's rule replays the arcs'
    first samples without their turn, so even the ideal robot misses the start; the limit is
    30 % of the path (1.97 m, 3.54 m), and a turn replayed unmirrored ends metres away."""
    played = play(mission, 'ideal', 'time', 0, **LAUNCH)
    _home_within(played, limit)


# --- real paths (test_mission_real_paths.py: paper noise, the README's calibration, 2 %) ----
def _on_mujoco(mission):
    """(mission, 'mujoco'), skipped where mujoco is not installed (the Noetic lane)."""
    try:
        import_mujoco()
        missing = None
    except ImportError as error:
        missing = 'mujoco not installed: %s' % error
    return pytest.param(mission, 'mujoco', marks=pytest.mark.skipif(missing is not None,
                                                                    reason=missing or ''))


@pytest.mark.parametrize('mission, base', [('real_turns_in_place', 'kinematic'),
                                           _on_mujoco('real_turns_in_place'),
                                           ('real_back_out', 'kinematic'),
                                           _on_mujoco('real_back_out')])
def test_real_paths_come_home_within_two_percent(mission, base):
    """Replaces mission_turns_in_place, mission_mujoco_turns_in_place, mission_back_out and
    mission_mujoco_back_out: home within 2 % of the path driven, the robot still."""
    played = play(mission, 'paper', 'closed_loop', 0, base=base, gyro_calibration=CALIBRATION, **LAUNCH)
    _home_within_share(played, 0.02)


def test_uncorrected_turns_in_place_come_home_within_two_percent():
    """Replaces mission_uncorrected: heading_correction off, ideal profile, 2 % of the path."""
    played = play('real_turns_in_place', 'ideal', 'closed_loop', 0,
                  **dict(LAUNCH, heading_correction=False))
    assert played.result.heading_correction.reason == 'heading correction off'
    _home_within_share(played, 0.02)


# --- pruning (test_mission_loops.py: ideal profile, return share 0.6, limit 0.1 m) ---------
@pytest.mark.parametrize('mission', ['loops_figure_eight', 'loops_side_room'])
def test_loops_are_pruned_and_come_home(mission):
    """Replaces mission_figure_eight_pruned and mission_side_room_pruned: the route and the
    return driven (ground truth) are shorter than 60 % of the recorded / forward path; home
    within 0.1 m."""
    played = play(mission, 'ideal', 'closed_loop', 0, **LAUNCH)
    result = played.result
    _home_within(played, 0.1)
    assert played.mission.pruning is not None and played.mission.pruning.cuts, 'nothing was cut'
    assert result.route_length < 0.6 * result.distance
    forward = _length(result.forward_path)
    assert forward > 0.9 * result.distance
    assert result.return_length < 0.6 * forward, '%.2f m back after %.2f m' % (result.return_length, forward)


# --- the paper's modes (test_mission.py: paper profile, Table VI test 1, seed 0, 1.3 m) -----
def test_distance_mode_comes_home_within_the_papers_worst_error():
    """Replaces mission_distance: the operator starts 40 s after the recording, vision fails
    4 s after it is done; home within 1.3 m (Table VI's worst), the robot still."""
    played = play('table6_test1', 'paper', 'distance', 0, start_delay=40.0, settle_time=4.0,
                  **dict(LAUNCH, prune_loops=False))
    _home_within(played, 1.3)


def test_time_mode_comes_home_within_the_papers_worst_error():
    """Replaces mission_time: time mode, home within 1.3 m, the robot still."""
    played = play('table6_test1', 'paper', 'time', 0, **dict(LAUNCH, prune_loops=False))
    _home_within(played, 1.3)


# --- odometry gaps (test_mission_real_paths.py with ~odometry_gap 3 s) -----------------------
GAP = 3.0
ODOM_TIMEOUT = ALLOWANCE_DEFAULTS['odom_timeout']


def _return_time_at(played, metres):
    """s after the return's start at which the robot (ground truth) had driven ``metres``."""
    run, start = played.run, _entered(played, 'returning')
    driven = 0.0
    for a, b, stamp in zip(run.path, run.path[1:], run.path_times[1:]):
        driven += math.hypot(b[0] - a[0], b[1] - a[1])
        if driven >= metres:
            return stamp - start
    raise AssertionError('the return drove only %.2f m' % driven)


@pytest.fixture
def holds(monkeypatch):
    """Every finished odometry hold (start, length) of the run, from each drive cycle's OdomGrace."""
    found, check = [], OdomGrace.check

    def checked(grace, now, odom_stamp):
        since = grace.holding_since
        decision = check(grace, now, odom_stamp)
        if since is not None and grace.holding_since is None:
            found.append((since, now - since))
        return decision
    monkeypatch.setattr(OdomGrace, 'check', checked)
    return lambda: sorted(found)


def _held(played, holds, state):
    """Total s held before (``rotating``) or after (``returning``) the return's start."""
    start = _entered(played, 'returning')
    return sum(length for at, length in holds() if (at >= start) == (state == 'returning'))


def test_an_odometry_gap_in_the_turn_holds_it_then_comes_home(holds):
    """Replaces mission_gap_in_turn: 3 s without odometry once 0.5 rad of the pi turn are turned
    (1 s after it starts at 0.6 rad/s); the turn holds for the gap minus odom_timeout, turns on,
    and the robot comes home within 2 % of the path. The harness's gaps count from the turn's
    and from the return's start: the return holds as long, 1 s after its start."""
    played = play('test_s_curve', 'paper', 'closed_loop', 0, gyro_calibration=CALIBRATION,
                  odometry_gaps=((1.0, GAP),), **LAUNCH)
    _home_within_share(played, 0.02)
    assert _held(played, holds, 'rotating') == pytest.approx(GAP - ODOM_TIMEOUT, abs=0.05), holds()
    assert _held(played, holds, 'returning') == pytest.approx(GAP - ODOM_TIMEOUT, abs=0.05), holds()


def test_an_odometry_gap_in_the_return_holds_it_then_comes_home(holds):
    """Replaces mission_gap_in_return: 3 s without odometry once the return has driven 1.5 m
    (ground truth); the return (not the turn) holds for the gap minus odom_timeout, the robot
    still meanwhile, drives on and comes home within 2 % of the path."""
    settings = dict(LAUNCH, gyro_calibration=CALIBRATION)
    at = _return_time_at(play('real_back_out', 'paper', 'closed_loop', 0, **settings), 1.5)
    played = play('real_back_out', 'paper', 'closed_loop', 0, odometry_gaps=((at, GAP),), **settings)
    _home_within_share(played, 0.02)
    assert _held(played, holds, 'rotating') == 0.0, holds()
    assert _held(played, holds, 'returning') == pytest.approx(GAP - ODOM_TIMEOUT, abs=0.05), holds()
    # still (no 5 mm step of the true path) from odom_timeout and 4 motor time constants after
    # the gap's start (the paper base coasts) to its end
    start, run = _entered(played, 'returning') + at, played.run
    still_from = start + ODOM_TIMEOUT + 4 * load_profile('paper')['motor_time_constant']
    moved = [t - start for t in run.path_times if still_from <= t < start + GAP - 0.01]
    assert not moved, 'moved at %s s into the gap' % moved


# --- resets and the clock moving back (test_mission_odometry_reset.py) --------------------
@pytest.mark.skip(reason='a kobuki reset_odometry re-anchored (expected home) is carried across by '
                  'ros/odometry.py (core/odometry_reset.ResetCarrier) before the Mission sees odometry; '
                  'the Mission takes only an untrusted reset (Inputs.reset), so the harness cannot play it')
def test_an_odometry_reset_in_the_return_is_re_anchored_and_comes_home():
    """Would replace mission_odometry_reset_return (deleted): the re-anchoring is
    interfaces.test's odometry_feed (every message carried in the old frame) and
    mission_odometry_reset_recording_paper.test (a re-anchored reset, then home)."""


def test_the_clock_moving_back_at_the_turn_aborts_naming_it_robot_still():
    """Replaces mission_odometry_reset_clock_rotating: the time moves back as the mission
    enters rotating; aborted at once naming the clock, no return, the robot still."""
    played = play('test_s_curve', 'ideal', 'closed_loop', 0, events=[('time_back', 'turn', 0.0)], **LAUNCH)
    assert played.result.status == 'aborted'
    assert 'time moved back' in played.result.reason and 'the pi turn' in played.result.reason
    assert played.mission.machine.outcome == outcome.CLOCK
    assert _states(played) == ['idle', 'recording', 'rotating', 'aborted']
    assert _ended_at(played) == pytest.approx(_entered(played, 'rotating'), abs=0.05)
    assert _still_after(played, _ended_at(played)) and _speed(played) < 1e-3


def test_the_clock_moving_back_in_the_return_aborts_naming_it_robot_still():
    """Replaces mission_odometry_reset_clock_returning: the time moves back after 1 m of the
    return (ground truth); aborted naming the clock, the robot still within 2 s, never home."""
    plain = play('test_s_curve', 'ideal', 'closed_loop', 0, **LAUNCH)
    at = _return_time_at(plain, 1.0)
    played = play('test_s_curve', 'ideal', 'closed_loop', 0, events=[('time_back', 'return', at)], **LAUNCH)
    assert played.result.status == 'aborted'
    assert 'time moved back' in played.result.reason and 'the return' in played.result.reason
    assert played.mission.machine.outcome == outcome.CLOCK
    assert _states(played) == ['idle', 'recording', 'rotating', 'returning', 'aborted']
    assert _still_after(played, _ended_at(played) + 2.0) and _speed(played) < 1e-3


# --- vision back (test_vision_back.py, case stop) ----------------------------------------
def test_vision_back_in_the_return_with_stop_is_recovered_robot_still():
    """Replaces vision_back_stop: on_vision_back stop, heading_correction off (the turn after
    vision_back_grace 5 s); vision back mid-return: recovered, the distance left in the
    reason, the base still within 1 s."""
    settings = dict(LAUNCH, heading_correction=False, on_vision_back='stop')
    plain = play('test_left_arc', 'ideal', 'closed_loop', 0, **settings)
    middle = (_ended_at(plain) - _entered(plain, 'returning')) / 2.0
    played = play('test_left_arc', 'ideal', 'closed_loop', 0, events=[('vision_back', 'return', middle)],
                  **settings)
    assert played.result.status == 'recovered', played.result.reason
    assert ' m left to home' in played.result.reason
    assert played.mission.machine.outcome == outcome.VISION_BACK
    assert _states(played) == ['idle', 'recording', 'rotating', 'returning', 'recovered']
    assert _still_after(played, _ended_at(played) + 1.0) and _speed(played) < 1e-3

"""The mission object's allowances and recording checks, played by the harness on the
simulated robot's ground truth: the pi turn's (rotate_pi's time_allowance, the client's
rotation_timeout, odom_grace), the return's (each goal's backstop, the whole return's
allowance, pauses not counted; core/mission_limits), vision_back_grace, and landmarks
lost to write failures judged before the turn (core/return_plan.recording_problem)."""
import errno
from types import SimpleNamespace

import pytest

from blind_navigation.core import outcome
from blind_navigation.core.gyro_bias import standstill_timeout
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.mission_files import LandmarkWriter
from blind_navigation.core.mission_limits import LIMIT_DEFAULTS, ReturnWatch
from blind_navigation.core.safety import return_allowance
from blind_navigation.sim import harness
from blind_navigation.sim.kobuki import load_profile
from test_mission_harness import _ended_at, _play, _speed, _states, _still_after

BLOCKED = 2000.0        # s the motors stay off: longer than any allowance here


def _params(**overrides):
    """The harness's controller params for the paper profile, with ``overrides``."""
    params = harness.default_params(harness._settings({}), load_profile('paper'))
    params.__dict__.update(overrides)
    return params


def _entered(played, new):
    return next(t for t, _, state, _ in played.mission.transitions if state == new)


def _aborted_still(played, says, code='TIMEOUT'):
    """Aborted saying ``says`` with the outcome code named ``code`` (core/outcome), the robot still."""
    assert played.result.status == 'aborted', played.mission.reason
    assert says in played.result.reason
    assert outcome.NAMES[played.mission.machine.outcome] == code, played.result.reason
    assert _still_after(played, _ended_at(played)) and _speed(played) < 1e-3


# --- the pi turn -------------------------------------------------------------------------------
def test_a_blocked_turn_ends_at_the_rotations_time_allowance():
    played = _play(('motors_off', 'turn', 0.0, BLOCKED))
    _aborted_still(played, 'time_allowance of 30 s')
    assert 'returning' not in _states(played)


def test_a_turn_beyond_rotation_timeout_ends_aborted_naming_it():
    """rotate_pi's allowance set beyond the client's backstop: rotation_timeout (the
    standstill's timeout + rotation_margin + vision_back_grace) from the loss ends it."""
    played = _play(('motors_off', 'turn', 0.0, BLOCKED), params=_params(time_allowance=600.0))
    _aborted_still(played, 'rotation_timeout')
    timeout = standstill_timeout(None) + LIMIT_DEFAULTS['rotation_margin']  # the harness's grace: 0
    assert _ended_at(played) - _entered(played, 'rotating') == pytest.approx(timeout, abs=0.05)


def test_a_takeover_in_the_turn_does_not_count_against_rotation_timeout():
    blocked = ('motors_off', 'turn', 0.0, BLOCKED)
    plain = _play(blocked, params=_params(time_allowance=600.0))
    held = _play(blocked, ('takeover', 'turn', 60.0, 40.0, (0.0, 0.0)), params=_params(time_allowance=600.0))
    _aborted_still(held, 'rotation_timeout')
    paused = _ended_at(held) - _ended_at(plain)
    assert 40.0 <= paused <= 40.0 + 2.0 + 0.05      # the takeover, and its takeover_wait at most


def test_odometry_that_stops_in_the_turn_ends_it_at_odom_grace():
    played = _play(odometry_gaps=((1.0, BLOCKED),))
    _aborted_still(played, 'odom_grace', 'ODOMETRY')
    assert 'returning' not in _states(played)


# --- the return --------------------------------------------------------------------------------
#: A return driver that never gives up by itself (the follower's stall and allowance out of
#: the way): the mission's own allowance, with the client's params, must end it.
ENDLESS = dict(stall_timeout=1e5, return_timeout_factor=100.0)
CLIENT = SimpleNamespace(**LIMIT_DEFAULTS)


def test_a_blocked_return_ends_at_the_followers_stall_timeout():
    _aborted_still(_play(('motors_off', 'return', 0.0, BLOCKED)), 'stall_timeout')


def test_the_whole_return_ends_at_its_allowance_pauses_not_counted():
    blocked = ('motors_off', 'return', 0.0, BLOCKED)
    plain = _play(blocked, params=_params(**ENDLESS), limits=CLIENT)
    allowance = return_allowance(plain.mission.landmarks, 3.0, 30.0)
    _aborted_still(plain, 'exceeded its time allowance of %.0f s' % allowance)
    assert _ended_at(plain) - _entered(plain, 'returning') == pytest.approx(allowance, abs=0.1)
    held = _play(blocked, ('takeover', 'return', 20.0, 50.0, (0.0, 0.0)), params=_params(**ENDLESS),
                 limits=CLIENT)
    _aborted_still(held, 'exceeded its time allowance')
    assert 50.0 <= _ended_at(held) - _ended_at(plain) <= 52.05     # + takeover_wait at most


def test_a_takeover_longer_than_the_allowance_still_comes_home():
    played = _play(('takeover', 'return', 5.0, 200.0, (0.0, 0.0)))
    assert played.result.status == 'home', played.mission.reason
    assert '1 operator takeover' in played.mission.reason and played.result.position_error < 0.1
    assert played.mission.machine.outcome == outcome.HOME


def test_the_return_watch_budget_and_a_remote_goals_backstop():
    landmarks = [Landmark(0.2, 0.0, 1.0, 5.0, 0.0)] * 2
    watch = ReturnWatch(landmarks, landmarks, None, 0.0)
    watch.goal(landmarks[0], 0.0)
    assert watch.problem(1.0, 3.9) is None                      # 1.5 x 2 m + 1 m
    assert watch.problem(1.0, 4.1).code == outcome.TIMEOUT
    assert 'more than its budget of 4.00 m' in watch.problem(1.0, 4.1).reason
    watch.resumed(100.0)                                        # a pause: the backstop anew
    assert watch.problem(120.0, 1.0) is None
    assert 'backstop' in watch.problem(155.1, 1.0).reason       # 5 x 5 s + 10 s


# --- vision back within the grace --------------------------------------------------------------
def test_without_heading_correction_vision_back_within_the_grace_goes_on_recording():
    loss = (('vision_lost', 'start', 20.0), ('vision_back', 'start', 22.0))
    graced = _play(*loss, heading_correction=False, vision_back_grace=5.0)
    assert _states(graced)[:5] == ['idle', 'recording', 'rotating', 'recording', 'rotating']
    assert graced.result.status == 'home', graced.mission.reason
    at_once = _play(*loss, heading_correction=False)        # paper.launch's grace: 0
    assert _states(at_once) == ['idle', 'recording', 'rotating', 'returning', 'home']
    assert at_once.result.status == 'home' and at_once.result.position_error < 0.1


# --- landmarks lost to write failures ----------------------------------------------------------
def _failing_writes(monkeypatch, first, last):
    """Appends of the landmarks ``first``..``last`` (1-based) fail: the disk is full."""
    write = LandmarkWriter._write_line

    def full(writer, text):
        if first <= writer.count + writer.lost + 1 <= last and not text.startswith('#'):
            raise OSError(errno.ENOSPC, 'No space left on device')
        return write(writer, text)
    monkeypatch.setattr(LandmarkWriter, '_write_line', full)


def test_landmarks_lost_while_driving_abort_at_the_loss(monkeypatch):
    """Known at the loss: no standstill, no turn (docs/safety.md, "Decide before the turn")."""
    _failing_writes(monkeypatch, 4, 5)
    played = _play()
    assert _states(played) == ['idle', 'recording', 'aborted']
    assert played.result.reason.startswith('vision lost, but 2 landmark(s) within the recording could '
                                           'not be written')
    assert played.mission.machine.outcome == outcome.STORAGE
    assert _still_after(played, _ended_at(played)) and _speed(played) < 1e-3


def test_landmarks_lost_at_the_end_abort_at_the_loss(monkeypatch):
    _failing_writes(monkeypatch, 15, 10 ** 6)          # the disk fills up and stays full
    played = _play()
    assert _states(played) == ['idle', 'recording', 'aborted']
    assert 'the last' in played.result.reason and 'the way back from here is unknown' in \
        played.result.reason
    assert played.mission.machine.outcome == outcome.STORAGE
    assert _still_after(played, _ended_at(played)) and _speed(played) < 1e-3


def test_landmarks_lost_standing_still_are_bridged_and_the_mission_comes_home(monkeypatch):
    _failing_writes(monkeypatch, 1, 2)
    played = _play(start_delay=5.0)
    assert played.result.status == 'home', played.mission.reason
    assert played.result.position_error < 0.1

"""The harness plays the recovery cases through core/mission.Mission (the object the
ROS layer drives): brief loss, bumps, takeovers, cancel, go_home, nothing to retrace,
vision back, resets; each checked on the simulated robot's ground truth."""
import contextlib
import math

import pytest

from blind_navigation.core import outcome
from blind_navigation.core.back_travel import BACK_TRAVEL_DEFAULTS
from blind_navigation.core.drive import FAILED, SUCCEEDED, Outcome
from blind_navigation.core.goal import make_goal
from blind_navigation.core.mission import Inputs, Mission
from blind_navigation.core.geometry import OdomState
from blind_navigation.core.odometry_reset import UNTRUSTED, is_untrusted_reset
from blind_navigation.core.route_follower import RouteFollower
from blind_navigation.core.store import load_landmarks
from blind_navigation.sim import harness
from blind_navigation.sim.harness import play
from blind_navigation.sim.mission import Mission as Script, load_mission

MISSION = 'table6_test1'        # 2.6 m, 30 s of driving
HOME_TOLERANCE = BACK_TRAVEL_DEFAULTS['home_tolerance']


def _play(*events, **settings):
    return play(MISSION, 'paper', settings.pop('mode', 'closed_loop'), 0, floor=False,
                events=events, **settings)


def _code(played):
    """The name of the mission's outcome code (core/outcome), as MissionStatus carries it."""
    return outcome.NAMES[played.mission.machine.outcome]


def _states(played):
    return [new for _, _, new, _ in played.mission.transitions]


def _speed(played):
    v, w = played.run.base.true_twist
    return abs(v) + abs(w)


def _still_after(played, t, within=0.02):
    """True if the robot moved at most ``within`` m (ground truth) after sim time ``t``."""
    run = played.run
    points = [p for p, stamp in zip(run.path, run.path_times) if stamp >= t]
    return all(math.hypot(p[0] - points[0][0], p[1] - points[0][1]) <= within for p in points)


def _ended_at(played):
    return played.mission.transitions[-1][0]


def test_the_plain_mission_comes_home():
    played = _play()
    assert played.result.status == 'home', played.result.reason
    assert played.result.position_error < 0.1 and _code(played) == 'HOME'
    assert _states(played) == ['idle', 'recording', 'rotating', 'returning', 'home']
    assert _speed(played) < 1e-3


def test_a_brief_loss_goes_on_recording_and_comes_home():
    played = _play(('vision_lost', 'start', 20.0), ('vision_back', 'start', 21.0))
    assert _states(played) == ['idle', 'recording', 'rotating', 'recording', 'rotating', 'returning',
                               'home']
    assert 'brief vision loss' in played.mission.transitions[3][3]
    plain = _play()
    assert played.result.distance == pytest.approx(plain.result.distance, abs=0.01)
    assert played.result.position_error < 0.1 and _speed(played) < 1e-3


def test_a_bump_during_the_return_pauses_then_comes_home():
    played = _play(('bumper', 'return', 5.0, 1.0))
    assert played.result.status == 'home', played.result.reason
    assert '1 bumper contact' in played.mission.reason and _code(played) == 'HOME'
    assert played.result.position_error < 0.1 and _speed(played) < 1e-3


def test_bumps_beyond_max_contacts_abort_with_the_robot_still():
    played = _play(*[('bumper', 'return', 5.0 + 5.0 * k, 0.5) for k in range(4)])
    assert played.result.status == 'aborted'
    assert 'max_contacts' in played.result.reason and _code(played) == 'CONTACTS'
    assert _still_after(played, _ended_at(played) + 0.5) and _speed(played) < 1e-3


def test_a_bumper_held_beyond_contact_timeout_aborts_with_the_robot_still():
    played = _play(('bumper', 'return', 5.0, 15.0))
    assert played.result.status == 'aborted' and 'contact_timeout' in played.result.reason
    assert _code(played) == 'CONTACTS'
    assert _ended_at(played) == pytest.approx(played.mission.transitions[-2][0] + 5.0 + 10.0, abs=0.1)
    assert _still_after(played, _ended_at(played) + 0.5) and _speed(played) < 1e-3


def test_a_small_takeover_rejoins_the_route_and_comes_home():
    played = _play(('takeover', 'return', 5.0, 1.0, (0.05, 0.0)))
    assert played.result.status == 'home', played.result.reason
    assert '1 operator takeover' in played.mission.reason and _code(played) == 'HOME'
    assert played.result.position_error < HOME_TOLERANCE and _speed(played) < 1e-3


def test_a_takeover_far_off_the_route_aborts_naming_it_never_a_false_home():
    turn_away, drive_off = ('takeover', 'return', 5.0, 2.0, (0.0, 0.8)), ('takeover', 'return', 7.0, 5.0,
                                                                         (0.25, 0.0))
    played = _play(turn_away, drive_off)
    assert played.result.status == 'aborted'
    assert 'off the route' in played.result.reason and 'operator takeover' in played.result.reason
    assert _code(played) == 'OFF_ROUTE'
    assert played.result.position_error > HOME_TOLERANCE     # truly far: so never home
    assert _speed(played) < 1e-3


@pytest.mark.parametrize('mode', ['closed_loop', 'time'])
def test_takeovers_never_end_home_far_from_the_start(mode):
    for length in (1.0, 4.0):
        played = _play(('takeover', 'return', 8.0, 1.5, (0.0, 0.8)),
                       ('takeover', 'return', 9.5, length, (0.2, 0.0)), mode=mode)
        assert not (played.result.status == 'home' and played.result.position_error > HOME_TOLERANCE), \
            played.mission.reason


def test_cancel_aborts_and_the_robot_stays_still():
    played = _play(('cancel', 'return', 5.0))
    assert played.result.status == 'aborted' and played.result.reason == 'cancelled by request'
    assert _code(played) == 'CANCELLED'
    assert _still_after(played, _ended_at(played) + 0.5)
    assert _speed(played) < 1e-3


def test_go_home_starts_the_return_before_vision_is_lost():
    duration = load_mission(MISSION).duration
    played = _play(('go_home', 'start', duration + 1.0), settle_time=10.0)
    assert played.result.status == 'home', played.result.reason
    rotating = [t for t in played.mission.transitions if t[2] == 'rotating']
    assert 'go_home' in rotating[0][3] and rotating[0][0] < duration + 2.0
    assert played.result.position_error < 0.1 and _speed(played) < 1e-3


def test_nothing_to_retrace_is_home_without_a_turn():
    played = play(Script([(0.0, 0.0, 5.0)], name='still'), 'paper', 'closed_loop', 0, floor=False)
    assert played.result.status == 'home'
    assert 'nothing to retrace' in played.mission.reason and _code(played) == 'NOTHING_TO_RETRACE'
    assert 'rotating' not in _states(played)
    assert played.result.position_error < 0.01 and _speed(played) < 1e-3


def test_vision_back_during_the_return_with_stop_is_recovered():
    played = _play(('vision_back', 'return', 5.0), on_vision_back='stop')
    assert played.result.status == 'recovered'
    assert 'left to home' in played.mission.reason and _code(played) == 'VISION_BACK'
    assert _still_after(played, _ended_at(played) + 0.5) and _speed(played) < 1e-3
    assert _play(('vision_back', 'return', 5.0)).result.status == 'home'     # on_vision_back home


@pytest.mark.parametrize('event, origin, says, code', [
    ('odometry_reset', 'return', 'odometry reset', 'ODOMETRY'),
    ('time_back', 'turn', 'time moved back', 'CLOCK'), ('time_back', 'return', 'time moved back', 'CLOCK'),
    ('cliff', 'return', 'safety stop: cliff', 'SAFETY_EVENT'),
    ('cliff', 'turn', 'safety stop: cliff', 'SAFETY_EVENT')])
def test_a_reset_the_time_moving_back_or_a_cliff_aborts_naming_it(event, origin, says, code):
    played = _play((event, origin, 2.0))
    assert played.result.status == 'aborted' and says in played.result.reason
    assert _code(played) == code, played.result.reason
    assert _still_after(played, _ended_at(played) + 0.5) and _speed(played) < 1e-3


@pytest.mark.parametrize('events', [False, True])
def test_an_untrusted_reset_while_recording_notes_a_gap_and_aborts_at_the_loss(events, monkeypatch,
                                                                               tmp_path):
    # the recording's file kept (the harness writes it in a temporary directory)
    monkeypatch.setattr(harness.tempfile, 'TemporaryDirectory',
                        lambda dir=None: contextlib.nullcontext(str(tmp_path)))
    played = _play(('odometry_reset', 'start', 12.0), event_sampling=events)
    odom, true = played.run.base.odom, played.run.base.true_pose
    assert math.hypot(true.x - odom.x, true.y - odom.y) > 0.5   # odometry restarted from 0
    assert _states(played) == ['idle', 'recording', 'aborted']      # no turn, never home
    assert played.result.reason.startswith('vision lost, but odometry reset not re-anchored')
    assert _code(played) == 'ODOMETRY'
    assert _still_after(played, _ended_at(played) + 0.5) and _speed(played) < 1e-3
    loaded = load_landmarks(str(tmp_path / 'landmarks.yaml'))
    assert [is_untrusted_reset(gap.reason) for gap in loaded.gaps] == [True], loaded.gaps
    assert 0 < loaded.labels.index(loaded.gaps[0].before) < len(loaded.labels) - 1


class _ListStore(object):
    def __init__(self):
        self.entries = []

    def append(self, landmark):
        self.entries.append(landmark)

    def note_gap(self, reason):
        self.entries.append(reason)


def test_a_reset_after_a_silence_counts_the_next_landmark_from_the_new_frame():
    # driving straight at 0.1 m/s, 2 s without odometry, then the driver from its origin
    store = _ListStore()
    mission = Mission(None, store, event_sampling=True, heading_correction=False)
    for k in range(301):
        mission.step(k * 0.02, Inputs(OdomState(0.002 * k, 0.0, 0.0, 0.1, 0.0, k * 0.02)))
    for k in range(101):
        t = 8.0 + k * 0.02
        mission.step(t, Inputs(OdomState(0.002 * k, 0.0, 0.0, 0.1, 0.0, t),
                               reset='%s (a test)' % UNTRUSTED if k == 0 else None))
    gap = store.entries.index('%s (a test)' % UNTRUSTED)
    assert 0 < gap < len(store.entries) - 1 and mission.state == 'recording'
    assert all(landmark.d <= 0.1 * landmark.T + 0.01 for landmark in store.entries[gap + 1:])


def test_new_mission_starts_again_from_a_terminal_state_only():
    mission = Mission(None, store=None)
    assert 'refused' in mission.new_mission(None)
    assert mission.cancel() is None and mission.state == 'aborted'
    assert mission.step(1.0).command == (0.0, 0.0)          # zero once, then nothing
    assert mission.step(1.1).command is None
    assert mission.new_mission(None) is None and mission.state == 'idle'
    assert 'refused' in mission.go_home()


def test_a_remote_goal_ended_at_once_is_not_sent_again():
    """A goal that fails on the step after it was sent (a cancel of every goal, the server's
    answer at once) aborts the mission, and no goal goes out after it (once the paper client
    sent the same goal every cycle until it was stopped: mission_cancel.test, CI run K)."""
    recorded = harness._Recorded(MISSION, 'paper', 0, harness._settings({'floor': False}), None, None)
    run, mission = recorded.run, recorded.owner
    mission.configure_return(remote_goals=True)
    step = mission.step(run.base.t, Inputs(odom=run.base.odom))
    assert step.goal is not None and step.goal[0] == 0
    cancelled = Outcome(FAILED, 'ended PREEMPTED: canceled after 0.000 m', outcome.CANCELLED)
    later = [mission.step(run.base.t + 0.02 * (k + 1), Inputs(odom=run.base.odom,
                                                              goal_result=cancelled if k == 0 else None))
             for k in range(50)]
    assert mission.state == 'aborted' and mission.reason.endswith('canceled after 0.000 m'), mission.reason
    assert [s.goal for s in later if s.goal is not None] == []


def test_remote_goals_are_sent_one_at_a_time_and_come_home():
    """The paper layout's protocol: the mission sends each goal (Step.goal), a fake server
    drives it (core/goal.make_goal on the shared follower, as back_travel_server) and answers
    with its Outcome (Inputs.goal_result); the mission publishes nothing meanwhile."""
    recorded = harness._Recorded(MISSION, 'paper', 0, harness._settings({'floor': False}), None, None)
    run, mission = recorded.run, recorded.owner
    mission.configure_return(remote_goals=True)
    step, sent, goal, follower, result = mission.step(run.base.t, Inputs(odom=run.base.odom)), [], None, \
        None, None
    while step.phase == 'goal':
        assert step.command is None
        if step.goal is not None:
            index, landmark = step.goal
            sent.append(index)
            follower = follower or RouteFollower(mission.route, recorded.params)
            goal = make_goal('closed_loop', landmark, recorded.params, follower, index)
            goal.start(mission.odom())
        command = goal.step(mission.odom()) if not goal.done else (0.0, 0.0)
        result = Outcome(SUCCEEDED, '') if goal.done else None
        run.advance(command if not goal.done else None)
        step = mission.step(run.base.t, Inputs(odom=run.base.odom, goal_result=result))
    harness._stop(run, mission, recorded.settings)
    assert sent == list(range(len(mission.landmarks)))
    assert mission.state == 'home', mission.reason
    end, start = run.base.true_pose, run.path_start
    assert math.hypot(end.x - start[0], end.y - start[1]) < 0.1
    assert _speed(harness.Played(None, mission, run)) < 1e-3

"""Behaviour findings of the safety_findings and mission_recover rostests played in the harness
through core/mission.Mission on the 2.3 m test_safety mission (ideal profile, closed_loop):
landmarks lost only while the robot stands still, an operator who pushes the robot on past
the start or wanders, go_home before the robot moved; each checked on ground truth."""
import errno
import math

import pytest

from blind_navigation.core import outcome
from blind_navigation.core.mission_files import LandmarkWriter
from blind_navigation.core.return_plan import STILL_LOSS_DISTANCE
from blind_navigation.sim.harness import play
from blind_navigation.sim.mission import Mission as Script

MISSION = 'test_safety'         # the rostests' mission (config/missions/test_safety.yaml)
#: m from the start a closed-loop return ends within on the ideal profile (findings_rig).
NORMAL_ACCURACY = 0.075
#: m a landmark taken standing still covers at most (ideal profile: none).
STANDING = 1e-4
HOME_WALK = ['idle', 'recording', 'rotating', 'returning', 'home']


def _play(*events, **settings):
    return play(MISSION, 'ideal', 'closed_loop', 0, floor=False, events=events, **settings)


def _states(played):
    return [new for _, _, new, _ in played.mission.transitions]


def _still_after(played, t, within=0.005):
    """True if the robot moved at most ``within`` m (ground truth) after sim time ``t``."""
    run = played.run
    points = [p for p, stamp in zip(run.path, run.path_times) if stamp >= t]
    return all(math.hypot(p[0] - points[0][0], p[1] - points[0][1]) <= within for p in points)


def _length(path):
    return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(path, path[1:]))


@pytest.fixture
def refused_while_still(monkeypatch):
    """The disk refuses the landmarks taken while the robot stands still (d below STANDING)
    and accepts the others (safety_findings' RLIMIT_FSIZE at the start and the end);
    returns the refused landmarks' d."""
    append, write = LandmarkWriter.append, LandmarkWriter._write_line
    refusing, refused = set(), []

    def appending(writer, landmark, sample=None):
        if landmark.d < STANDING:
            refusing.add(id(writer))
            refused.append(landmark.d)
        try:
            return append(writer, landmark, sample)
        finally:
            refusing.discard(id(writer))

    def writing(writer, text):
        if id(writer) in refusing and not text.startswith('#'):
            raise OSError(errno.ENOSPC, 'No space left on device')
        return write(writer, text)
    monkeypatch.setattr(LandmarkWriter, 'append', appending)
    monkeypatch.setattr(LandmarkWriter, '_write_line', writing)
    return refused


def test_landmarks_lost_only_while_standing_still_are_bridged_and_come_home(refused_while_still):
    """safety_findings' former TestK (issue 28): losses at the start and at the end, one hole."""
    played = _play(start_delay=5.0, settle_time=3.0)
    mission, result = played.mission, played.result
    loaded = mission.loaded
    assert _states(played) == HOME_WALK, mission.reason
    assert result.position_error <= NORMAL_ACCURACY
    assert loaded.missing >= 2, 'fewer than two landmarks lost at the start'
    assert len(refused_while_still) > loaded.missing, 'nothing was lost at the end'
    assert sum(refused_while_still) <= STILL_LOSS_DISTANCE
    assert len(loaded.gaps) == 1, "the start's loss is not one hole"
    assert _length(result.forward_path) - loaded.total_distance < 0.02, 'driven path missing from the file'
    assert 'while the robot stood still' in mission.warning and 'while the robot stood still' in mission.reason
    assert outcome.NAMES[mission.machine.outcome] == 'HOME'
    assert _still_after(played, mission.transitions[-1][0] + 0.5)


@pytest.mark.parametrize('turning, says', [(0.0, ('operator takeover', 'moved the robot')),
                                           (0.1, ('operator takeover',))])
def test_a_long_takeover_is_never_home_far_from_the_start(turning, says):
    """mission_recover's former edges 2 and 3: the operator pushes the robot on (90 s at
    0.05 m/s: 4.5 m, past the start) or wanders (turning 0.1 rad/s) mid-return."""
    played = _play(('takeover', 'return', 3.0, 90.0, (0.05, turning)))
    result, mission = played.result, played.mission
    assert result.status in ('home', 'aborted'), mission.reason
    if result.status == 'home':
        assert result.position_error <= 0.03 * result.distance, mission.reason
    else:
        for text in says:
            assert text in mission.reason
    assert _still_after(played, mission.transitions[-1][0] + 0.5)


def test_go_home_before_moving_is_home_without_a_turn():
    """mission_recover's former edges 4: nothing to retrace."""
    played = play(Script([(0.0, 0.0, 5.0)], name='still'), 'ideal', 'closed_loop', 0, floor=False,
                  events=(('go_home', 'start', 3.0),), settle_time=30.0)
    mission = played.mission
    assert played.result.status == 'home', mission.reason
    assert _states(played) == ['idle', 'recording', 'home']
    assert 'nothing to retrace' in mission.reason
    assert outcome.NAMES[mission.machine.outcome] == 'NOTHING_TO_RETRACE'
    assert played.result.position_error < 0.005 and _still_after(played, 0.0)

"""Unit tests of core/safety.py: per-goal limits, clamping, Kobuki events,
allowances, progress persistence and the resume decision."""
import math
import os

import pytest

from blind_navigation.core.landmark import Landmark
from blind_navigation.core.safety import (ProgressError, ReturnProgress, SafetyEvents,
                                          VelocityLimits, expected_duration, file_digest,
                                          goal_limits, landmarks_from_flat, load_progress,
                                          position_check, progress_path, recorded_speed,
                                          resume_check, return_allowance, save_progress)


def test_clamp_keeps_curvature_and_limits_both():
    limits = VelocityLimits(0.2, 0.5)
    v, w = limits.clamp(0.4, 0.4)
    assert (v, w) == pytest.approx((0.2, 0.2))
    v, w = limits.clamp(0.1, -1.0)
    assert (v, w) == pytest.approx((0.05, -0.5))
    assert w / v == pytest.approx(-10.0)
    assert limits.clamp(0.1, 0.2) == (0.1, 0.2)
    assert limits.clamp(float('nan'), 0.1) == (0.0, 0.0)
    assert limits.clamp(0.1, float('inf')) == (0.0, 0.0)
    assert VelocityLimits(0.0, 1.0).clamp(0.3, 0.3) == (0.0, 0.0)


def test_goal_never_faster_than_recorded():
    slow = Landmark(0.05, 0.0, 0.12, 2.0, 0.0)          # mean 0.06 m/s > end speed
    assert recorded_speed(slow) == pytest.approx(0.06)
    limits = goal_limits(slow, max_v=0.5, max_w=1.0, correction_w=0.3)
    assert limits.max_v == pytest.approx(0.06)
    assert limits.max_w == pytest.approx(0.3)
    arc = Landmark(0.1, -0.4, 0.1, 1.0, 0.0)
    assert goal_limits(arc, 0.5, 1.0, 0.3) == pytest.approx((0.1, 0.7))
    fast = Landmark(0.6, 0.9, 1.2, 2.0, 0.0)             # configured limits win
    assert goal_limits(fast, 0.5, 1.0, 0.3) == pytest.approx((0.5, 1.0))
    with pytest.raises(ValueError):
        goal_limits(slow, -0.1, 1.0)


def test_safety_events_kobuki_layout():
    events = SafetyEvents()
    assert events.update('bumper', 1, 1) == 'bumper center pressed'
    assert events.active == ['bumper center pressed']
    assert events.update('cliff', 0, 1) == 'cliff left cliff'
    assert events.update('wheel_drop', 1, 1) == 'wheel drop right dropped'
    assert events.update('bumper', 1, 0) is None         # released
    assert events.update('cliff', 0, 0) is None          # floor
    assert events.active == ['wheel drop right dropped']
    assert events.update('wheel_drop', 1, 0) is None     # raised
    assert events.active == []
    assert events.update('bumper', 7, 1) == 'bumper sensor 7 pressed'
    with pytest.raises(ValueError):
        events.update('sonar', 0, 1)


def test_allowances():
    lm = Landmark(0.1, 0.0, 0.3, 2.0, 0.0)
    assert expected_duration(lm) == pytest.approx(3.0)   # d / v > T
    stopped = Landmark(0.0, 0.0, 0.03, 2.0, 0.0)
    assert expected_duration(stopped, slowest_v=0.03) == pytest.approx(2.0)
    assert return_allowance([lm, stopped], 3.0, 30.0) == pytest.approx(3 * 5.0 + 30.0)


def progress(tmp_path, **changes):
    values = dict(landmark_file=str(tmp_path / 'landmarks-1.yaml'), digest='abc', landmarks=10,
                  anchor=[1.0, 2.0], frame_id='odom', completed=4, position=[0.5, 2.0],
                  status='returning', updated=1000.0)
    values.update(changes)
    return ReturnProgress(**values)


def test_progress_round_trip_is_atomic_and_next_to_the_landmark_file(tmp_path):
    path = progress_path(str(tmp_path / 'landmarks.yaml'))
    assert path == str(tmp_path / 'landmarks.progress.yaml')
    saved = progress(tmp_path)
    save_progress(path, saved)
    assert load_progress(path) == saved
    assert sorted(os.listdir(str(tmp_path))) == ['landmarks.progress.yaml']   # no temporary left
    save_progress(path, saved._replace(completed=5))
    assert load_progress(path).completed == 5
    assert load_progress(str(tmp_path / 'none.progress.yaml')) is None


@pytest.mark.parametrize('text', ['[1, 2', 'just text', 'landmark_file: x\n',
                                  None])
def test_bad_progress_is_refused_naming_the_file(tmp_path, text):
    path = str(tmp_path / 'p.progress.yaml')
    if text is None:
        save_progress(path, progress(tmp_path, anchor=[1.0, float('nan')]))
    else:
        with open(path, 'w') as stream:
            stream.write(text)
    with pytest.raises(ProgressError) as error:
        load_progress(path)
    assert path in str(error.value)


def test_resume_decision(tmp_path):
    p = progress(tmp_path)
    assert resume_check(p, 1010.0, 'abc', 600.0)[0] == 'resume'
    assert resume_check(p._replace(status='home'), 1010.0, 'abc', 600.0)[0] == 'ignore'
    assert resume_check(p, 1000.0 + 601.0, 'abc', 600.0)[0] == 'ignore'    # too old
    assert resume_check(p, 900.0, 'abc', 600.0)[0] == 'ignore'             # from the future
    decision, why = resume_check(p._replace(status='rotating'), 1010.0, 'abc', 600.0)
    assert decision == 'abort' and 'pi turn' in why
    decision, why = resume_check(p, 1010.0, 'changed', 600.0)
    assert decision == 'abort' and 'changed' in why
    assert resume_check(p, 1010.0, None, 600.0)[0] == 'abort'
    assert resume_check(p._replace(anchor=None), 1010.0, 'abc', 600.0)[0] == 'abort'
    assert position_check(p, [0.6, 2.1], 0.5) is None
    assert 'moved' in position_check(p, [2.0, 2.0], 0.5)
    assert 'no odometry' in position_check(p, None, 0.5)


def test_file_digest_changes_with_content(tmp_path):
    path = tmp_path / 'f.yaml'
    path.write_text('a')
    first = file_digest(str(path))
    path.write_text('b')
    assert file_digest(str(path)) != first


def test_landmarks_from_flat():
    values = [0.1, 0.0, 0.2, 2.0, 0.0, 0.1, 0.1, 0.1, 1.0, 0.1]
    assert landmarks_from_flat(values)[1] == Landmark(0.1, 0.1, 0.1, 1.0, 0.1)
    assert landmarks_from_flat([]) == []
    with pytest.raises(ValueError, match='multiple of 5'):
        landmarks_from_flat(values[:7])
    with pytest.raises(ValueError, match='completed landmark 2: d is negative'):
        landmarks_from_flat(values[:5] + [0.1, 0.0, -1.0, 2.0, 0.0])
    with pytest.raises(ValueError, match='not finite'):
        landmarks_from_flat([math.nan, 0.0, 0.1, 1.0, 0.0])

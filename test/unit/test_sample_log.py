"""The sampling publisher's record of its samples (core/sample_log.py), and the check a
restarted saver makes of the publisher's answer before it continues its file from it
(the right recording, the samples from its last one on in order, one odometry row each,
finite; anything else leaves the gap entry); its ticks (Ticks) are the mission's samples."""
import math
from types import SimpleNamespace

import pytest

from blind_navigation.core.geometry import OdomState
from blind_navigation.core.geometry import wrap_angle
from blind_navigation.core.mission_record import MissionRecording
from blind_navigation.core.sample_log import START, SampleLog, Ticks, answer_problem
from blind_navigation.core.store import SampleMark


def state(t):
    return OdomState(0.1 * t, 0.0, 0.0, 0.1, 0.0, t)


def test_entry_zero_is_the_start_and_samples_number_from_one():
    log = SampleLog(2.5, state(2.5))
    assert log.last == 0
    assert [log.append('sample', t, 0.0, 1.0, state(t)) for t in (3.5, 4.5)] == [1, 2]
    entries = log.since(0)
    assert [e.seq for e in entries] == [0, 1, 2] and entries[0].command == START
    assert entries[2].x == pytest.approx(0.45) and entries[2].period == 1.0
    assert [e.seq for e in log.since(2)] == [2]
    assert log.since(3) is None


def test_past_capacity_the_oldest_half_is_dropped():
    log = SampleLog(0.0, state(0.0), capacity=4)
    for t in range(1, 7):
        log.append('sample', float(t), 0.0, 1.0, state(float(t)))
    assert log.last == 6 and log.first > 0
    assert log.since(0) is None
    assert [e.seq for e in log.since(log.first)] == list(range(log.first, 7))
    assert log.since(6)[0].stamp == 6.0


def test_what_every_recorder_confirmed_is_dropped_up_to_the_oldest_confirmation():
    log = SampleLog(0.0, state(0.0))
    for t in range(1, 11):
        log.append('sample', float(t), 0.0, 1.0, state(float(t)))
    log.confirm('topic.yaml', 7)
    assert log.first == 7 and [e.seq for e in log.since(7)] == [7, 8, 9, 10]
    log.confirm('service.yaml', 4)          # a second recorder behind: nothing it needs goes
    assert log.first == 7 and log.since(4) is None
    log.confirm('service.yaml', 9)
    assert log.first == 7                   # the topic recorder still needs 7 on
    log.confirm('topic.yaml', 10)
    assert log.first == 9 and log.since(9)[0].stamp == 9.0


def test_a_confirmation_of_a_sample_not_taken_or_older_than_before_changes_nothing():
    log = SampleLog(0.0, state(0.0))
    for t in range(1, 6):
        log.append('sample', float(t), 0.0, 1.0, state(float(t)))
    log.confirm('a.yaml', 9)
    assert log.first == 0 and log.confirmed == {}
    log.confirm('a.yaml', 3)
    log.confirm('a.yaml', 2)
    assert log.first == 3 and log.confirmed == {'a.yaml': 3}
    assert [e.seq for e in log.since(3)] == [3, 4, 5]


def test_capacity_must_hold_two():
    with pytest.raises(ValueError):
        SampleLog(0.0, state(0.0), capacity=1)



def sample(seq, yaw=0.1, period=1.0):
    return SimpleNamespace(seq=seq, yaw=yaw, period=period)


def answer(seqs, recording=7.5, **columns):
    n = len(seqs)
    rows = {name: columns.get(name, [0.1 * k for k in range(n)]) for name in 'xyvw'}
    return SimpleNamespace(recording=recording, message='', samples=[sample(s) for s in seqs], **rows)


def test_an_answer_from_the_files_last_sample_on_fits():
    assert answer_problem(answer([4, 5, 6]), SampleMark(7.5, 4)) == ''
    assert answer_problem(answer([0, 1]), None) == ''          # an empty file: from the start


@pytest.mark.parametrize('bad, mark, words', [
    (answer([]), SampleMark(7.5, 4), 'no samples'),
    (answer([4, 5], recording=9.0), SampleMark(7.5, 4), 'recording'),
    (answer([5, 6]), SampleMark(7.5, 4), 'in order'),
    (answer([4, 6]), SampleMark(7.5, 4), 'in order'),
    (answer([4, 5], x=[0.0]), SampleMark(7.5, 4), 'columns'),
    (answer([4, 5], y=[0.0, math.nan]), SampleMark(7.5, 4), 'finite'),
])
def test_an_answer_that_does_not_fit_is_refused_with_the_reason(bad, mark, words):
    assert words in answer_problem(bad, mark)


def test_a_non_finite_yaw_is_refused():
    bad = answer([4, 5])
    bad.samples[1].yaw = math.inf
    assert 'finite' in answer_problem(bad, SampleMark(7.5, 4))


def driven(seconds, rate=50.0):
    """OdomStates of a drive: straight, a left arc, a stop, then backwards, at ``rate`` Hz."""
    x = y = yaw = 0.0
    states = []
    for index in range(int(seconds * rate)):
        t = index / rate
        v, w = (0.2, 0.0) if t < 6 else (0.2, 0.3) if t < 12 else (0.0, 0.0) if t < 15 else (-0.1, 0.0)
        states.append(OdomState(x, y, yaw, v, w, 100.0 + t))
        x, y, yaw = x + v * math.cos(yaw) / rate, y + v * math.sin(yaw) / rate, yaw + w / rate
    return states


@pytest.mark.parametrize('events', [False, True])
def test_the_publishers_ticks_are_the_missions_samples(events):
    """The sampling publisher steps the mission's recording over Ticks: the same ticks, periods
    and yaws (motion events, the rate switch and the final partial cycle included)."""
    config = SimpleNamespace(straight_period=2.0, curved_period=1.0, deadband=0.01,
                             event_sampling=events, heading_correction=False)
    unkept = SimpleNamespace(append=lambda taken: None, note_gap=lambda reason: None)
    mission, publisher = MissionRecording(unkept, config), MissionRecording(unkept, config, Ticks())
    states = driven(20.0)
    landmarks, ticks = [], []
    for recording, out in ((mission, landmarks), (publisher, ticks)):
        recording.begin(states[0])
        for odom in states[1:]:
            out += recording.step(odom, odom.stamp)
        out += recording.end(states[-1], states[-1].stamp)
    assert len(ticks) >= 10 and {period for _, _, period in ticks} >= {2.0, 1.0}   # 20 s, <= 2 s each
    assert [(lm.T, lm.psi, lm.v) for lm in landmarks] == \
        [(period, wrap_angle(yaw), state.v) for state, yaw, period in ticks]
    assert ticks[-1][0] is states[-1] and publisher.recorder.total_distance == 0.0

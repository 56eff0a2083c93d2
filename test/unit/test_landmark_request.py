"""The service recorder's requests in the one-process mission (core/landmark_request):
a requested landmark is taken by the mission's recording in time order with its own
samples (d from the previous landmark, T and psi the request's, the two-rate ticks
unchanged); bad requests, 'final', and requests outside the recording save nothing and
say why (the state named)."""
import math

import pytest

from blind_navigation.core import landmark_request as lr
from blind_navigation.core.geometry import OdomState
from blind_navigation.core.mission_files import LandmarkWriter
from blind_navigation.core.mission import Inputs, Mission
from blind_navigation.core.return_plan import write_loss
from blind_navigation.core.store import label_for, load_landmarks

SPEED, RATE = 0.1, 50       # m/s along +x, odometry Hz


class FileStore(object):
    """The mission's store as the owner's: a real landmark file, labels returned."""

    def __init__(self, path):
        self.path, self.writer = path, LandmarkWriter(path, fsync=False, metadata={})

    def append(self, landmark):
        return self.writer.append(landmark)

    def note_gap(self, reason):
        self.writer.note_gap(reason)

    def load(self):
        self.writer.close()
        return load_landmarks(self.path)

    def loss(self):
        return write_loss(self.writer, '')


def odom(k):
    t = k / float(RATE)
    return OdomState(SPEED * t, 0.0, 0.0, SPEED, 0.0, t)


class Run(object):
    """A mission recording straight at SPEED, stepped one odometry state at a time."""

    def __init__(self, tmp_path, **settings):
        self.store = FileStore(str(tmp_path / 'landmarks.yaml'))
        self.mission = Mission(None, self.store, **dict(dict(heading_correction=False), **settings))
        self.k, self.stored = 0, []

    def until(self, t, **inputs):
        while self.k / float(RATE) <= t + 1e-9:
            step = self.mission.step(self.k / float(RATE), Inputs(odom(self.k), **inputs))
            self.stored += [(self.k / float(RATE), lm) for lm in step.stored]
            self.k += 1

    def ask(self, command='sample', yaw=0.3, period=0.7, stamp=None):
        answers = []
        request = lr.LandmarkRequest(command, yaw, period, stamp, answers.append)
        lr.hand_in(self.mission, request)
        return request, answers


@pytest.mark.parametrize('event_sampling', [False, True])
def test_a_requested_landmark_splits_the_path_between_two_ticks(tmp_path, event_sampling):
    run = Run(tmp_path, event_sampling=event_sampling)
    run.until(3.0)
    request, answers = run.ask(stamp=3.0)
    run.until(6.0)
    assert answers == [request] and request.answer[1] == ''
    landmarks = [lm for _, lm in run.stored]
    taken = landmarks.index(next(lm for lm in landmarks if lm.T == 0.7))
    assert request.answer[0] == label_for(taken + 1)            # its label in the file
    mine, after = landmarks[taken:taken + 2]
    assert mine.psi == pytest.approx(0.3) and mine.v == pytest.approx(SPEED)
    assert mine.d == pytest.approx(SPEED * 1.0, abs=1e-6)        # from the 2 s tick to 3 s
    assert after.d == pytest.approx(SPEED * 1.0, abs=1e-6)       # from the request to the 4 s tick
    assert after.T == 2.0 and run.mission.state == 'recording'  # the 4 s tick as without it
    assert [t for t, lm in run.stored if lm is after] == [4.0 + run.mission.recording.latency]
    written = run.store.load()
    assert len(written.landmarks) == len(landmarks)
    assert written.landmarks[written.labels.index(request.answer[0])].T == pytest.approx(0.7)


def test_an_unstamped_request_is_taken_at_the_next_state(tmp_path):
    run = Run(tmp_path, event_sampling=False)
    run.until(2.5)
    request, _ = run.ask(stamp=0)
    run.until(2.52)
    assert request.answer[0] and run.stored[-1][1].d == pytest.approx(SPEED * 0.52, abs=1e-6)


@pytest.mark.parametrize('command, yaw, period, says', [
    ('final', 0.0, 1.0, "'final' is not taken here"),
    ('../../tmp/x.yaml', 0.0, 1.0, 'unknown command'),
    ('sample', float('nan'), 1.0, 'finite'),
    ('sample', 0.0, float('inf'), 'finite'),
    ('sample', 0.0, 0.0, 'T > 0'),
    ('sample', 0.0, 0.001, 'bad sample'),       # 0.19 m in 0.001 s: beyond the base
])
def test_bad_requests_save_nothing_and_say_why(tmp_path, command, yaw, period, says):
    run = Run(tmp_path, event_sampling=False)
    run.until(5.8)
    request, _ = run.ask(command, yaw, period, stamp=5.9)
    run.until(6.0)
    label, why = request.answer
    assert label == '' and says in why and why.startswith('refused')
    assert [lm.T for _, lm in run.stored] == [2.0, 2.0, 2.0]
    assert run.stored[-1][1].d == pytest.approx(SPEED * 2.0, abs=1e-6)     # from the 4 s tick


def test_before_the_recording_and_before_the_last_landmark_are_refused(tmp_path):
    run = Run(tmp_path, event_sampling=False)
    request, _ = run.ask(stamp=0.5)
    assert 'no odometry yet' in request.answer[1] and 'idle' in request.answer[1]
    run.until(2.5)
    request, _ = run.ask(stamp=1.5)
    assert 'before the last landmark' in request.answer[1]


def test_outside_the_recording_the_answer_names_the_state(tmp_path):
    run = Run(tmp_path, event_sampling=False, heading_correction=True)     # a standstill follows
    run.until(4.5)
    pending, _ = run.ask(stamp=9.0)         # not due before the loss
    assert run.mission.go_home() is None
    run.until(4.6)
    assert run.mission.state == 'rotating'
    assert pending.answer[0] == '' and 'recording ended' in pending.answer[1]
    request, _ = run.ask(stamp=4.7)
    assert request.answer[0] == '' and 'the mission is rotating, not recording' in request.answer[1]
    assert run.mission.cancel() is None
    request, _ = run.ask(stamp=4.7)
    assert 'the mission is aborted, not recording' in request.answer[1]


def test_a_request_not_taken_in_time_is_withdrawn(tmp_path):
    run = Run(tmp_path, event_sampling=False)
    run.until(2.5)
    request, _ = run.ask(stamp=100.0)
    run.until(3.0)
    assert request.answer is None
    lr.withdraw(run.mission, request, 2.0)
    assert request.answer == ('', 'not taken within 2.0 s: no odometry state after its stamp')
    assert run.mission.recording.requested == []
    assert math.isclose(run.stored[-1][0], 2.0)

"""The mission owner's ROS-facing pieces without a master: its return progress
(core/progress_keeper.MissionProgress), the plain heading correction it keeps
(core/progress.heading_record) and the release of a safety halt (ros/motion.MotionOutput)."""
import math
import os
import types

import pytest

rospy = pytest.importorskip('rospy')

from blind_navigation.core import outcome
from blind_navigation.core import mission_state as state  # noqa: E402
from blind_navigation.core.geometry import OdomState  # noqa: E402
from blind_navigation.core.heading_correction import GyroCorrection  # noqa: E402
from blind_navigation.core.landmark import Landmark  # noqa: E402
from blind_navigation.core.progress import heading_record, load_progress, progress_path  # noqa: E402
from blind_navigation.core.route import build_route  # noqa: E402
from blind_navigation.ros.motion import MotionOutput  # noqa: E402
from blind_navigation.core.progress_keeper import MissionProgress  # noqa: E402

LANDMARKS = [Landmark(0.1, 0.0, 0.2, 2.0, 0.0), Landmark(0.1, 0.0, 0.2, 2.0, 0.0)]


class Log(object):
    """A RoleLog that keeps its lines."""

    def __init__(self):
        self.lines = []

    def __getattr__(self, level):
        return lambda text, *args: self.lines.append((level, text % args))


def _landmark_file(tmp_path):
    path = tmp_path / 'landmarks.yaml'
    path.write_text(''.join('landmark_%06d: {data: [%r, %r, %r, %r, %r]}\n'
                            % ((n + 1,) + tuple(l)) for n, l in enumerate(LANDMARKS)))
    return str(path)


def _mission():
    """What MissionProgress reads of a core/mission.Mission."""
    m = types.SimpleNamespace(
        raw=None, last=None, state=state.RECORDING, correction=None, corrector=None,
        reference=None, anchor=None,
        drive=None, config=types.SimpleNamespace(heading_correction=True), cancelled=None)
    m.cancel = lambda reason=None, code=None: setattr(m, 'cancelled', reason) or setattr(m, 'code', code)
    return m


def _progress(path, log=None):
    return MissionProgress(path, lambda: 'mission_1', lambda: 'odom', log or Log())


def _at(mission, x, stamp):
    mission.last = OdomState(x, 0.0, math.pi, 0.1, 0.0, stamp)


def _return(progress, m):
    """Lose vision at x 0.4 after two landmarks, turn, drive the first goal back (as the Mission
    does: its correction at the turn's commit, its drive's goals once returning)."""
    path = progress_path(progress.landmark_file)
    m.state, m.anchor = state.ROTATING, (0.4, 0.0)
    m.reference = OdomState(0.4, 0.0, 0.0, 0.0, 0.0, 5.0)
    m.correction = GyroCorrection(1e-4, 0.0, 1e-5, float('inf'), 3, 'bias', 'no calibration')
    progress.update(m, None)
    assert load_progress(path).status == state.ROTATING
    m.state = state.RETURNING
    m.drive = types.SimpleNamespace(goals=[('2', LANDMARKS[1]), ('1', LANDMARKS[0])], index=0)
    progress.update(m, build_route(LANDMARKS, m.anchor))
    started = load_progress(path)
    assert (started.status, started.landmarks, started.completed) == (state.RETURNING, 2, 0)
    assert started.route['heading']['correction'][3] is None    # inf: plain data cannot hold it
    _at(m, 0.4, 6.0)
    progress.update(m, None)
    m.drive.index = 1
    _at(m, 0.2, 8.0)
    progress.update(m, None)
    done = load_progress(path)
    assert (done.completed, done.position) == (1, [0.2, 0.0])
    assert done.travelled == pytest.approx(0.2)


def test_the_progress_follows_the_return_to_home(tmp_path):
    progress, m = _progress(_landmark_file(tmp_path)), _mission()
    _return(progress, m)
    _at(m, 0.0, 11.0)
    progress.ending(state.HOME, 'travelled 2 landmarks')
    home = load_progress(progress_path(progress.landmark_file))
    assert (home.status, home.completed, home.reason) == (state.HOME, 2, 'travelled 2 landmarks')
    progress.forget()
    assert progress.progress is None


@pytest.mark.parametrize('end', [state.DOCKED, state.HOME, state.ABORTED])
def test_a_docking_ends_the_return_home_and_its_end_leaves_the_progress_alone(tmp_path, end):
    progress, m = _progress(_landmark_file(tmp_path)), _mission()
    _return(progress, m)
    _at(m, 0.0, 11.0)
    progress.ending(state.DOCKING, 'travelled 2 landmarks')
    progress.ending(end, 'docked on the charger')
    home = load_progress(progress_path(progress.landmark_file))
    assert (home.status, home.completed, home.reason) == (state.HOME, 2, 'travelled 2 landmarks')


def test_an_abort_before_the_turn_keeps_no_progress(tmp_path):
    progress, m = _progress(_landmark_file(tmp_path)), _mission()
    progress.update(m, None)
    progress.ending(state.ABORTED, 'before the pi turn: no landmark')
    assert not os.path.exists(progress_path(progress.landmark_file))


def test_a_return_whose_start_was_not_kept_does_not_end_home_in_the_file(tmp_path):
    progress, m = _progress(_landmark_file(tmp_path)), _mission()
    m.state, m.anchor, m.reference = state.ROTATING, (0.4, 0.0), OdomState(0.4, 0, 0, 0, 0, 5.0)
    m.correction = GyroCorrection(0.0, 0.0, 1e-5, 1e-5, 3, 'bias', '')
    progress.update(m, None)
    os.unlink(progress.landmark_file)       # its digest cannot be read: the start is not kept
    m.state, m.drive = state.RETURNING, types.SimpleNamespace(goals=[('1', LANDMARKS[0])], index=0)
    progress.update(m, build_route(LANDMARKS[:1], m.anchor))
    _at(m, 0.2, 8.0)
    progress.ending(state.HOME, 'travelled 1 landmarks')
    assert load_progress(progress_path(progress.landmark_file)).status == state.ROTATING
    assert [level for level, _ in progress.log.lines] == ['warn', 'warn']


PARAMS = types.SimpleNamespace(max_v=0.7, max_w=2.0, resume_timeout=600.0, resume_max_offset=0.5)


def test_a_return_left_by_a_previous_run_is_kept_to_resume(tmp_path):
    path = _landmark_file(tmp_path)
    _return(_progress(path), _mission())        # then the process dies
    restarted = _mission()
    kept = _progress(path).first_state(restarted, lambda: [0.2, 0.0], PARAMS)
    assert restarted.cancelled is None
    assert (kept.done, kept.anchor, kept.travelled) == (1, (0.4, 0.0), pytest.approx(0.2))
    assert kept.correction.bias == 1e-4 and kept.reference.x == 0.4


def test_a_return_whose_landmark_file_changed_is_aborted_as_the_default_layer_does(tmp_path):
    path = _landmark_file(tmp_path)
    _return(_progress(path), _mission())
    with open(path, 'a') as extra:
        extra.write('landmark_000003: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n')
    restarted = _mission()
    assert _progress(path).first_state(restarted, lambda: [0.2, 0.0], PARAMS) is None
    assert restarted.cancelled == 'landmark file %s changed since the return started' % path
    assert restarted.code == outcome.RESUME
    kept = load_progress(progress_path(path))
    assert (kept.status, kept.reason) == (state.ABORTED, restarted.cancelled)
    again = _mission()
    _progress(path).first_state(again, lambda: [0.2, 0.0], PARAMS)     # the next start: idle
    assert again.cancelled is None


def test_the_kept_correction_is_plain_data():
    reference = OdomState(1.0, 2.0, 0.5, 0.0, 0.0, 7.0)
    plain = heading_record(GyroCorrection(1e-4, 0.0, 1e-5, math.inf, 3, 'bias', ''), reference)
    assert plain == {'correction': [1e-4, 0.0, 1e-5, None, 3, 'bias', ''],
                     'reference': [1.0, 2.0, 0.5, 7.0], 'frame': None}


class Safety(object):
    def __init__(self):
        self.active, self.trips = (), []

    def on_trip(self, callback):
        self.trips.append(callback)


def test_only_a_safety_halt_is_released_and_only_once_the_contact_is_over():
    safety = Safety()
    output = MotionOutput('back_travel_server', 0.3, 1.0, safety=safety)
    output._send = lambda v, w: None
    safety.active = ('bumper: left',)
    safety.trips[0]('bumper: left')
    output.contact_over()
    assert output.halted == 'safety: bumper: left'      # still pressed
    safety.active = ()
    output.contact_over()
    assert output.halted is None
    output.halt('cancelled by request')
    output.contact_over()
    assert output.halted == 'cancelled by request'

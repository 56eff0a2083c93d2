"""A return interrupted by a restart, resumed by a new core/mission.Mission from the progress
file the mission owner keeps (core/progress_keeper.MissionProgress, core/resume.kept_return),
driven against the simulated robot (sim/harness.py); files that cannot be resumed are refused
with the default layer's reasons."""
import math
import os
import re
import time
import types

import pytest

pytest.importorskip('rospy')

from blind_navigation.core import outcome
from blind_navigation.core import mission_state as state  # noqa: E402
from blind_navigation.core.mission_files import LandmarkWriter  # noqa: E402
from blind_navigation.core.mission import RESUMED, Mission  # noqa: E402
from blind_navigation.core.mission_drive import FINAL, GOAL, HANDOVER  # noqa: E402
from blind_navigation.core.progress import load_progress, progress_path, save_progress  # noqa: E402
from blind_navigation.core.resume import ABORT, RESUME, kept_return, resume_from_file  # noqa: E402
from blind_navigation.core.progress_keeper import MissionProgress  # noqa: E402
from blind_navigation.sim import harness  # noqa: E402

MISSION, PROFILE, SEED = 'table6_test1', 'paper', 0


class Log(object):
    def __getattr__(self, level):
        return lambda text, *args: None


def _recorded(tmp_path):
    """The mission recorded and turned by pi on the simulated robot, its landmarks in a file the
    progress names: (the harness's recording, the landmark file, the MissionProgress)."""
    recorded = harness._Recorded(MISSION, PROFILE, SEED, harness._settings({}), str(tmp_path), None)
    assert recorded.turned, recorded.owner.reason
    path = str(tmp_path / 'landmarks.yaml')
    writer = LandmarkWriter(path, fsync=False, metadata={'mission': MISSION})
    for landmark in recorded.loaded.landmarks:
        writer.append(landmark)
    writer.close()
    progress = MissionProgress(path, lambda: 'mission_1', lambda: 'odom', Log())
    progress.update(recorded.owner, None)       # the turn began: the progress too
    return recorded, path, progress


def _drive(run, mission, progress, until):
    """Step ``mission`` on ``run`` (its progress kept each step) while ``until()`` is false."""
    step = harness._step(run, mission, run.events)
    while step[0].phase in (GOAL, HANDOVER, FINAL, 'turned') and not until():
        run.advance(step[0].command)
        step = harness._step(run, mission, run.events)
        progress.update(mission, mission.route)
    return step


def _interrupted(tmp_path):
    """The return driven to its middle goal, then the process dies (the robot left still)."""
    recorded, path, progress = _recorded(tmp_path)
    m, run = recorded.owner, recorded.run
    half = len(recorded.loaded.landmarks) // 2
    _drive(run, m, progress, lambda: getattr(m.drive, 'index', 0) >= half)
    for _ in range(100):        # the robot stops: no command any more
        run.advance((0.0, 0.0))
    assert load_progress(progress_path(path)).completed == half
    return recorded, path


def _error(run):
    end, start = run.base.true_pose, run.path_start
    return math.hypot(end.x - start[0], end.y - start[1])


def test_a_return_resumed_after_a_restart_comes_home_on_ground_truth(tmp_path):
    recorded, path = _interrupted(tmp_path)
    run, before = recorded.run, recorded.owner
    odom = run.base.odom
    decision = resume_from_file(progress_path(path), time.time(), [odom.x, odom.y], 'mission_1')
    assert decision.action == RESUME, decision.reason
    kept, problem = kept_return(decision.progress, progress_path(path))
    assert problem is None
    resumed = Mission(before.params, before.store, kept=kept, **vars(before.config))
    assert (resumed.state, resumed.reason) == (state.RETURNING, RESUMED)
    progress = MissionProgress(path, lambda: 'mission_1', lambda: 'odom', Log())
    progress.progress, progress.route = decision.progress, kept.route
    _drive(run, resumed, progress, lambda: resumed.phase == 'ended')
    harness._stop(run, resumed, harness._settings({}))
    assert resumed.state == state.HOME, resumed.reason
    assert resumed.drive.index == len(kept.loaded.landmarks)
    uninterrupted = harness.play(MISSION, PROFILE, seed=SEED).result
    assert uninterrupted.status == 'home'
    # the restart costs no accuracy: home as close as the same return without one, +- 2 cm
    assert _error(run) < 0.1 and abs(_error(run) - uninterrupted.position_error) < 0.02, (
        _error(run), uninterrupted.position_error)


def aged(reason):
    """``reason`` with the age it names ("updated N s ago") as N."""
    return re.sub(r'updated \d+ s ago', 'updated N s ago', reason)


@pytest.mark.parametrize('spoil, says', [
    ('landmarks', 'landmark file %(path)s changed since the return started'),
    ('old', 'too old to resume'),
    ('moved', 'from where the return stopped (resume_max_offset'),
    ('turn', 'restarted during the pi turn: the heading is unknown'),
])
def test_a_stale_or_mismatching_progress_is_refused_with_the_default_layers_reasons(
        tmp_path, spoil, says):
    recorded, path = _interrupted(tmp_path)
    kept_path, odom = progress_path(path), recorded.run.base.odom
    progress, position = load_progress(kept_path), [odom.x, odom.y]
    if spoil == 'landmarks':
        with open(path, 'a') as extra:
            extra.write('landmark_009999: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n')
    elif spoil == 'old':
        save_progress(kept_path, progress._replace(started=progress.started - 3600.0,
                                                     updated=progress.updated - 3600.0))
    elif spoil == 'moved':
        position = [odom.x + 1.0, odom.y]
    else:
        save_progress(kept_path, progress._replace(status=state.ROTATING))
    params = types.SimpleNamespace(max_v=0.7, max_w=2.0, resume_timeout=600.0,
                                   resume_max_offset=0.5)
    restarted = types.SimpleNamespace(cancelled=None)
    restarted.cancel = lambda reason=None, code=None: setattr(restarted, 'cancelled', reason) or \
        setattr(restarted, 'code', code)
    default = resume_from_file(kept_path, time.time(), position, 'mission_1')   # owner:=layer's
    owner = MissionProgress(path, lambda: 'mission_1', lambda: 'odom', Log())
    assert owner.first_state(restarted, lambda: position, params) is None
    # each reads the wall clock itself: the age it names may differ by a second
    assert (default.action, aged(restarted.cancelled)) == (ABORT, aged(default.reason))
    assert restarted.code == outcome.RESUME
    assert says % {'path': os.path.realpath(path)} in restarted.cancelled
    assert load_progress(kept_path).status == state.ABORTED

"""Unit tests of core/progress.py: the life of a return's progress, the file
(atomic, validated on load), and the resume decision (finding 7: a progress
file that cannot be trusted aborts, never ignores; completed: 99 is refused)."""
import errno
import os

import pytest
import yaml

from blind_navigation.core import mission_state as state
from blind_navigation.core.files import StorageError
from blind_navigation.core.landmark import Landmark
from blind_navigation.core.progress import (FORMAT_VERSION, ProgressError, ReturnProgress,
                                            file_digest, load_progress, progress_path,
                                            save_progress)
from blind_navigation.core.route import build_route
from blind_navigation.core.progress_keeper import MissionProgress
from blind_navigation.core.resume import (ABORT, IGNORE, RESUME, resume_decision, resume_from_file,
                                          settle_abort)

NOW = 1.7e9


@pytest.fixture
def mission(tmp_path):
    """A recorded landmark file behind its symlink, and where its progress goes."""
    real = tmp_path / 'landmarks-20240101-120000.yaml'
    real.write_text(''.join('landmark_%06d: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n' % i
                            for i in range(1, 11)))
    link = tmp_path / 'landmarks.yaml'
    link.symlink_to(real.name)
    return str(link), progress_path(str(link)), file_digest(str(real))


ROUTE = build_route([Landmark(0.1, 0.0, 0.2, 2.0, 0.0)] * 10, (1.0, 2.0))


def route_record(route, heading=None):
    """The progress's ``route`` field, as core/progress_keeper writes it."""
    return {'route': route.to_lists(), 'heading': heading}


def returning(link, digest, completed=4):
    progress = ReturnProgress.begin(link, [1.0, 2.0], 'odom', NOW - 100.0, mission='m1')
    progress = progress.start(digest, 10, NOW - 90.0, route=route_record(ROUTE))
    return progress.goal_done(completed, NOW - 10.0, position=[0.5, 2.0], travelled=0.6)


def test_life_of_a_return(mission):
    link, path, digest = mission
    progress = ReturnProgress.begin(link, (1.0, 2.0), 'odom', NOW, mission='m1')
    assert progress.status == state.ROTATING and progress.landmark_file == os.path.realpath(link)
    assert progress.anchor == [1.0, 2.0] and progress.digest == '' and progress.started == NOW
    progress = progress.start(digest, 3, NOW + 1, route=route_record(ROUTE, {'yaw': 0.5}))
    assert progress.status == state.RETURNING and progress.route['heading'] == {'yaw': 0.5}
    assert progress.route['route'] == ROUTE.to_lists()
    progress = progress.goal_done(1, NOW + 2, position=[0.9, 2.0], travelled=0.1)
    progress = progress.goal_done(3, NOW + 3)
    assert (progress.completed, progress.position, progress.travelled) == (3, [0.9, 2.0], 0.1)
    progress = progress.finish(state.HOME, 'travelled 0.3 m', NOW + 4)
    assert not progress.unfinished and progress.reason == 'travelled 0.3 m'
    save_progress(path, progress)
    assert load_progress(path) == progress


def test_misuse_of_the_life_is_refused(mission):
    link, _, digest = mission
    with pytest.raises(ProgressError, match='needs its anchor'):
        ReturnProgress.begin(link, None, 'odom', NOW).start(digest, 3, NOW)
    rotating = ReturnProgress.begin(link, [0.0, 0.0], 'odom', NOW)
    with pytest.raises(ValueError, match='while returning'):
        rotating.goal_done(1, NOW)
    with pytest.raises(ProgressError, match='digest'):
        rotating.start('not a digest', 3, NOW)
    with pytest.raises(ValueError, match='finite point|point must be'):
        ReturnProgress.begin(link, [float('nan'), 0.0], 'odom', NOW)
    progress = rotating.start(digest, 3, NOW)
    with pytest.raises(ValueError, match='from 0 up to 3'):
        progress.goal_done(4, NOW)
    with pytest.raises(ValueError, match='rotating'):
        progress.start(digest, 3, NOW)
    with pytest.raises(ProgressError, match='home needs every landmark'):
        progress.finish(state.HOME, 'early', NOW)
    aborted = progress.finish(state.ABORTED, 'bumper', NOW)
    with pytest.raises(ValueError, match='already ended aborted'):
        aborted.finish(state.HOME, 'late', NOW)
    with pytest.raises(ValueError, match='home, aborted or recovered'):
        progress.finish(state.IDLE, '', NOW)
    with pytest.raises(ProgressError, match='route'):
        progress._replace(route=[[0.0, float('inf')]]).checked()
    broken = route_record(ROUTE)
    broken['route']['x'][1] = float('inf')
    with pytest.raises(ProgressError, match='route: route field x must be a list of finite'):
        progress._replace(route=broken).checked()
    with pytest.raises(ProgressError, match='route heading must be a map'):
        progress._replace(route=route_record(ROUTE, [1.0])).checked()


def test_progress_file_is_atomic_next_to_the_landmark_file(mission, tmp_path):
    link, path, digest = mission
    assert path == str(tmp_path / 'landmarks.progress.yaml')
    progress = returning(link, digest)
    save_progress(path, progress)
    assert load_progress(path) == progress
    save_progress(path, progress.goal_done(5, NOW))
    assert load_progress(path).completed == 5
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        'landmarks-20240101-120000.yaml', 'landmarks.progress.yaml', 'landmarks.yaml']
    assert load_progress(str(tmp_path / 'none.progress.yaml')) is None


def test_a_planted_symlink_at_the_temporary_name_is_not_written_through(mission, tmp_path):
    """Finding 6: landmarks.progress.yaml.tmp symlinked elsewhere was overwritten."""
    link, path, digest = mission
    victim = tmp_path / 'victim.txt'
    victim.write_text('precious\n')
    os.symlink(str(victim), path + '.tmp')
    save_progress(path, returning(link, digest))
    assert victim.read_text() == 'precious\n'
    assert load_progress(path).completed == 4


def test_a_symlink_as_the_progress_file_is_untrusted(mission, tmp_path):
    link, path, digest = mission
    other = tmp_path / 'elsewhere.yaml'
    save_progress(str(other), returning(link, digest))
    os.symlink(str(other), path)
    decision = resume_from_file(path, NOW, [0.5, 2.0])
    assert decision.action == ABORT and 'is a symlink' in decision.reason


def test_a_failed_write_keeps_the_old_progress_and_names_the_file(mission, tmp_path, monkeypatch):
    link, path, digest = mission
    save_progress(path, returning(link, digest, completed=4))
    real_fsync = os.fsync

    def failing_fsync(fd):
        if os.readlink('/proc/self/fd/%d' % fd).startswith(path.replace('landmarks.progress',
                                                                         '.landmarks.progress')):
            raise OSError(errno.EIO, os.strerror(errno.EIO))
        return real_fsync(fd)

    monkeypatch.setattr(os, 'fsync', failing_fsync)
    with pytest.raises(StorageError) as error:
        save_progress(path, returning(link, digest, completed=5))
    assert path in str(error.value) and 'Input/output error (EIO)' in str(error.value)
    assert error.value.errno == errno.EIO
    monkeypatch.undo()
    assert load_progress(path).completed == 4
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith('.')) == []


def test_a_progress_that_cannot_be_written_is_a_warning_and_no_stale_file_is_left(mission, monkeypatch):
    # issue 28: a full disk makes the progress unwritable; the return goes on (no resume after
    # a crash), and an older step's file is removed so a restart cannot resume from it
    link, path, digest = mission
    warned, changes = [], []
    log = type('Log', (), {'warn': lambda self, *args: warned.append(args[0] % args[1:])})()
    keeper = MissionProgress(link, None, None, log, changed=lambda: changes.append(keeper.warning))
    keeper.save(returning(link, digest, completed=4))
    assert load_progress(path).completed == 4 and keeper.warning == '' and changes == []
    real_write = os.write

    def full(fd, data):
        if os.readlink('/proc/self/fd/%d' % fd).startswith(os.path.dirname(path)):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real_write(fd, data)
    monkeypatch.setattr(os, 'write', full)
    keeper.save(returning(link, digest, completed=5))
    keeper.save(returning(link, digest, completed=6))
    assert keeper.progress.completed == 6                   # kept in memory: the return goes on
    assert not os.path.lexists(path)
    assert len(warned) == 1 and len(changes) == 1 and warned[0] == keeper.warning
    assert keeper.warning.startswith('the return progress cannot be written (cannot write %s' % path)
    assert keeper.warning.endswith('No space left on device (ENOSPC)): no resume after a crash')
    monkeypatch.undo()
    keeper.save(returning(link, digest, completed=7))
    assert load_progress(path).completed == 7 and keeper.warning == '' and changes[-1] == ''


# --- the resume decision -------------------------------------------------------

def test_resume_rules(mission):
    link, _, digest = mission
    p = returning(link, digest)
    assert resume_decision(p, NOW, digest, [0.6, 2.1]).action == RESUME
    assert resume_decision(p, NOW, digest, [0.6, 2.1], mission='m1').action == RESUME
    decision = resume_decision(p, NOW, digest, [0.6, 2.1], mission='m2')
    assert decision.action == IGNORE and 'left over from mission m1' in decision.reason
    ended = p.finish(state.ABORTED, 'x', NOW - 5)
    assert resume_decision(ended, NOW, digest, None).action == IGNORE
    for now, words in ((NOW + 700.0, 'too old'), (NOW - 60.0, 'in the future')):
        decision = resume_decision(p, now, digest, [0.6, 2.1])
        assert decision.action == ABORT and words in decision.reason
    rotating = ReturnProgress.begin(link, [1.0, 2.0], 'odom', NOW - 5)
    assert 'pi turn' in resume_decision(rotating, NOW, digest, [1.0, 2.0]).reason
    assert 'changed' in resume_decision(p, NOW, '0' * 64, [0.6, 2.1]).reason
    assert 'gone' in resume_decision(p, NOW, None, [0.6, 2.1]).reason
    assert 'no odometry' in resume_decision(p, NOW, digest, None).reason
    decision = resume_decision(p, NOW, digest, [2.0, 2.0])
    assert decision.action == ABORT and 'moved' in decision.reason


def test_resume_from_file(mission, tmp_path):
    link, path, digest = mission
    assert resume_from_file(path, NOW, [0.5, 2.0]).action == IGNORE     # no file
    save_progress(path, returning(link, digest))
    decision = resume_from_file(path, NOW, [0.5, 2.0], mission='m1')
    assert decision.action == RESUME and decision.progress.completed == 4
    assert decision.progress.route['route'] == ROUTE.to_lists()
    # the progress says 12 landmarks, the (unchanged) file holds 10: refused by count
    save_progress(path, returning(link, digest)._replace(landmarks=12))
    decision = resume_from_file(path, NOW, [0.5, 2.0])
    assert decision.action == ABORT and 'landmarks: the return was over 12' in decision.reason
    (tmp_path / 'landmarks-20240101-120000.yaml').write_text(
        'landmark_000001: {data: [0.1, 0.0, 0.3, 2.0, 0.0]}\n')
    assert 'changed' in resume_from_file(path, NOW, [0.5, 2.0]).reason
    (tmp_path / 'landmarks-20240101-120000.yaml').write_text('landmark_000001: [1]\n')
    assert 'landmark file unusable' in resume_from_file(path, NOW, [0.5, 2.0]).reason


def edited(link, digest, field, value):
    document = yaml.safe_load(yaml.safe_dump(dict([('format', FORMAT_VERSION)] + list(
        returning(link, digest)._asdict().items()))))
    if value is KeyError:
        del document[field]
    else:
        document[field] = value
    return yaml.safe_dump(document)


UNTRUSTED = {
    'not yaml': (lambda link, digest: 'completed: [4\n', 'not a YAML text'),
    'binary': (lambda link, digest: b'\xff\xfe\x00garbage', 'not a YAML text'),
    'empty': (lambda link, digest: '', 'must be a map'),
    'a list': (lambda link, digest: '- 1\n- 2\n', 'must be a map'),
    'truncated': (lambda link, digest: edited(link, digest, 'status', 'x')[:40], None),
    'no format': (lambda link, digest: edited(link, digest, 'format', KeyError), 'format'),
    'missing field': (lambda link, digest: edited(link, digest, 'anchor', KeyError), 'anchor: missing'),
    'unknown field': (lambda link, digest: edited(link, digest, 'speed', 3), 'speed: unknown'),
    'completed 99': (lambda link, digest: edited(link, digest, 'completed', 99), 'completed'),
    'completed negative': (lambda link, digest: edited(link, digest, 'completed', -1), 'completed'),
    'completed text': (lambda link, digest: edited(link, digest, 'completed', '4'), 'completed'),
    'completed float': (lambda link, digest: edited(link, digest, 'completed', 4.0), 'completed'),
    'completed bool': (lambda link, digest: edited(link, digest, 'completed', True), 'completed'),
    'landmarks negative': (lambda link, digest: edited(link, digest, 'landmarks', -10), 'landmarks'),
    'nan anchor': (lambda link, digest: edited(link, digest, 'anchor', [float('nan'), 2.0]),
                   'anchor'),
    'null anchor': (lambda link, digest: edited(link, digest, 'anchor', None), 'anchor'),
    'short anchor': (lambda link, digest: edited(link, digest, 'anchor', [1.0]), 'anchor'),
    'inf position': (lambda link, digest: edited(link, digest, 'position', [float('inf'), 0]),
                     'position'),
    'unknown status': (lambda link, digest: edited(link, digest, 'status', 'flying'), 'status'),
    'idle status': (lambda link, digest: edited(link, digest, 'status', 'idle'), 'status'),
    'bad digest': (lambda link, digest: edited(link, digest, 'digest', 'abc'), 'digest'),
    'relative file': (lambda link, digest: edited(link, digest, 'landmark_file', 'lm.yaml'),
                      'landmark_file'),
    'nan updated': (lambda link, digest: edited(link, digest, 'updated', float('nan')), 'updated'),
    'negative travelled': (lambda link, digest: edited(link, digest, 'travelled', -1.0),
                           'travelled'),
    'bad route': (lambda link, digest: edited(link, digest, 'route', [[0.0, 'x']]), 'route'),
    'version 1 route': (lambda link, digest: edited(link, digest, 'route', {
        'route': [[1.0, 2.0], [0.0, 0.0]], 'heading': None}), 'route'),
    'version 1 file': (lambda link, digest: edited(link, digest, 'format', 1),
                       'format: must be 2, got 1 (written by an older version'),
    'empty mission': (lambda link, digest: edited(link, digest, 'mission', ''), 'mission'),
    'started after updated': (lambda link, digest: edited(link, digest, 'started', NOW + 1e6),
                              'started'),
}


@pytest.mark.parametrize('name', sorted(UNTRUSTED))
def test_finding7_a_progress_file_that_cannot_be_trusted_aborts(mission, name):
    link, path, digest = mission
    make, field = UNTRUSTED[name]
    content = make(link, digest)
    with open(path, 'wb') as stream:
        stream.write(content if isinstance(content, bytes) else content.encode())
    with pytest.raises(ProgressError) as error:
        load_progress(path)
    if field:
        assert field in str(error.value)
    decision = resume_from_file(path, NOW, [0.5, 2.0], mission='m1')
    assert decision.action == ABORT and decision.progress is None
    assert path in decision.reason and (field is None or field in decision.reason), decision.reason


@pytest.mark.parametrize('kind', ['directory', 'fifo'])
def test_a_progress_path_that_is_not_a_file_aborts(mission, kind):
    link, path, digest = mission
    os.mkdir(path) if kind == 'directory' else os.mkfifo(path)
    decision = resume_from_file(path, NOW, [0.5, 2.0])
    assert decision.action == ABORT and path in decision.reason
    assert ('a directory' if kind == 'directory' else 'a FIFO') in decision.reason


def test_settle_abort_records_it_and_keeps_the_bad_file(mission, tmp_path):
    link, path, digest = mission
    with open(path, 'w') as stream:
        stream.write('completed: 99\n')
    decision = resume_from_file(path, NOW, [0.5, 2.0])
    aside = settle_abort(path, decision, NOW)
    assert open(aside).read() == 'completed: 99\n'
    settled = load_progress(path)
    assert settled.status == state.ABORTED and 'cannot trust' in settled.reason
    assert resume_from_file(path, NOW + 1, [0.5, 2.0]).action == IGNORE     # the next start is clean
    # a trusted but unresumable progress is marked aborted in place
    save_progress(path, returning(link, digest))
    decision = resume_from_file(path, NOW, [5.0, 5.0])
    assert decision.action == ABORT and settle_abort(path, decision, NOW) is None
    settled = load_progress(path)
    assert settled.status == state.ABORTED and settled.completed == 4 and 'moved' in settled.reason
    with pytest.raises(ValueError):
        settle_abort(path, resume_from_file(path, NOW, [0.5, 2.0]), NOW)

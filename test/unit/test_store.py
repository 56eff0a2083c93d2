"""The YAML landmark store: format, round trips, torn entries, bad files, the
kinds of landmark_file, write failures, and a restarted recorder continuing
its mission's file."""
import datetime
from contextlib import closing
import errno
import math
import os

import pytest
import yaml

from blind_navigation.core.files import StorageError
from blind_navigation.core.landmark import Landmark, landmark_from_values
from blind_navigation.core.mission_files import (RESTART_GAP, LandmarkWriter, mission_number,
                                                 next_mission_id, open_mission_file)
from blind_navigation.core.store import Gap, LandmarkFileError, SampleMark, format_entry, load_landmarks


PATH = [Landmark(0.0861, 0.0012, 0.1718, 2.0, 0.0131),
        Landmark(0.0859, 0.0964, 0.0862, 1.0, 0.0610),
        Landmark(0.09, -0.097, 0.09, 1.0, -3.1),
        Landmark(1e-5, -2.5e-7, 0.0, 2.0, -3.14159)]


def write(path, landmarks=PATH, **kwargs):
    with closing(LandmarkWriter(str(path), **kwargs)) as writer:
        for landmark in landmarks:
            writer.append(landmark)
    return writer


def test_round_trip(tmp_path):
    path = tmp_path / 'lm.yaml'
    writer = write(path, metadata={'odom_topic': '/odom'})
    loaded = load_landmarks(str(path))
    assert loaded.landmarks == PATH
    assert loaded.labels == ['landmark_%06d' % i for i in range(1, 5)]
    assert loaded.metadata['odom_topic'] == '/odom'
    assert loaded.warnings == []
    assert writer.count == 4
    assert loaded.total_distance == pytest.approx(sum(l.d for l in PATH))


def test_numbers_keep_six_significant_digits(tmp_path):
    path = tmp_path / 'lm.yaml'
    exact = Landmark(0.0861234567, -0.0964123456, 13.2345678, 20.0, math.pi)
    write(path, [exact])
    stored = load_landmarks(str(path)).landmarks[0]
    for kept, original in zip(stored, exact):
        assert kept == pytest.approx(original, rel=5e-6, abs=1e-12)  # half a unit in the 6th digit


def test_file_is_plain_yaml_in_the_interface_format(tmp_path):
    path = tmp_path / 'lm.yaml'
    write(path, fsync=False)
    document = yaml.safe_load(path.read_text())
    assert document['landmark_000001'] == {'data': [0.0861, 0.0012, 0.1718, 2.0, 0.0131]}
    lines = [l for l in path.read_text().splitlines() if l.startswith('landmark_')]
    assert lines[0] == 'landmark_000001: {data: [0.0861, 0.0012, 0.1718, 2.0, 0.0131]}'
    assert all(not key.startswith('landmark_') or set(value) == {'data'}
               for key, value in document.items())


def test_writer_never_overwrites(tmp_path):
    path = tmp_path / 'lm.yaml'
    write(path)
    with pytest.raises(FileExistsError):
        LandmarkWriter(str(path))
    assert load_landmarks(str(path)).landmarks == PATH


def test_torn_last_entry_is_dropped_and_reported(tmp_path):
    path = tmp_path / 'lm.yaml'
    write(path)
    with open(str(path), 'a') as stream:
        stream.write(format_entry('landmark_000005', PATH[0])[:25])   # killed mid-write
    loaded = load_landmarks(str(path))
    assert loaded.landmarks == PATH
    assert len(loaded.warnings) == 1 and 'torn' in loaded.warnings[0]


def test_start_mission_file_keeps_earlier_missions(tmp_path):
    link = str(tmp_path / 'dir' / 'landmarks.yaml')
    with closing(open_mission_file(link, fsync=False)) as first:
        for landmark in PATH:
            first.append(landmark)
    with closing(open_mission_file(link, fsync=False)) as second:
        second.append(PATH[0])
    assert first.path != second.path and os.path.realpath(link) == second.path
    assert load_landmarks(link).landmarks == PATH[:1]
    assert load_landmarks(first.path).landmarks == PATH



def test_new_missions_are_numbered_on_from_the_launch_id():
    assert [next_mission_id(m) for m in ('mission_vm_1', 'mission_vm_1#2', None, 'mission#9')] == [
        'mission_vm_1#2', 'mission_vm_1#3', 'mission#2', 'mission#10']
    assert [mission_number(m) for m in ('mission_vm_1', 'mission_vm_1#2', None, 'a#b')] == [1, 2, 1, 1]


def test_a_new_mission_id_opens_a_new_file_and_keeps_the_old_one_byte_identical(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    with closing(open_mission_file(link, 'launch', fsync=False)) as writer:
        for landmark in PATH:
            writer.append(landmark)
        writer.finish()
        first = writer.path
    with open(first, 'rb') as stream:
        before = stream.read()
    with closing(open_mission_file(link, next_mission_id('launch'), fsync=False)) as writer:
        writer.append(PATH[0])
        second = writer.path
    assert second != first and os.path.realpath(link) == second
    with open(first, 'rb') as stream:
        assert stream.read() == before
    assert load_landmarks(link).landmarks == PATH[:1]

def test_start_mission_file_archives_a_regular_file(tmp_path):
    link = tmp_path / 'landmarks.yaml'
    write(link)
    with closing(open_mission_file(str(link), fsync=False)) as writer:
        target = writer.path
    archived = [p for p in tmp_path.iterdir() if p.name.startswith('landmarks-') and str(p) != target]
    assert len(archived) == 1 and load_landmarks(str(archived[0])).landmarks == PATH
    assert os.path.realpath(str(link)) == target


BAD_FILES = {
    'empty': ('', 'no landmarks'),
    'not yaml': ('landmark_000001: {data: [1, 2\n  - : ]]\n', 'not valid YAML'),
    'not a map': ('- 1\n- 2\n', 'top level must be a map'),
    'wrong type': ('landmark_000001: {data: [0.1, 0.0, x, 1.0, 0.0]}\n', 'd is not a number'),
    'nan': ('landmark_000001: {data: [.nan, 0.0, 0.1, 1.0, 0.0]}\n', 'v is not finite'),
    'inf': ('landmark_000001: {data: [0.1, .inf, 0.1, 1.0, 0.0]}\n', 'w is not finite'),
    'negative d': ('landmark_000001: {data: [0.1, 0.0, -0.1, 1.0, 0.0]}\n', 'd is negative'),
    'zero T': ('landmark_000001: {data: [0.1, 0.0, 0.1, 0.0, 0.0]}\n', 'T must be positive'),
    'too fast': ('landmark_000001: {data: [2.0, 0.0, 0.1, 1.0, 0.0]}\n', 'exceeds the limit'),
    'four values': ('landmark_000001: {data: [0.1, 0.0, 0.1, 1.0]}\n', 'five numbers'),
    'no data': ('landmark_000001: [0.1, 0.0, 0.1, 1.0, 0.0]\n', 'data sequence'),
    'duplicate': ('landmark_000001: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n'
                  'landmark_000001: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n', 'duplicate key'),
    'out of order': ('landmark_000002: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n'
                     'landmark_000001: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n', 'out of recording order'),
}


@pytest.mark.parametrize('name', sorted(BAD_FILES))
def test_bad_file_is_refused_naming_file_and_entry(tmp_path, name):
    text, reason = BAD_FILES[name]
    path = tmp_path / 'bad.yaml'
    path.write_text(text)
    with pytest.raises(LandmarkFileError) as error:
        load_landmarks(str(path))
    message = str(error.value)
    assert str(path) in message and reason in message, message
    if 'landmark_000001: {data' in text and name not in ('duplicate', 'out of order', 'not yaml'):
        assert 'landmark_000001' in message


def test_missing_file_is_refused(tmp_path):
    with pytest.raises(LandmarkFileError) as error:
        load_landmarks(str(tmp_path / 'nope.yaml'))
    assert 'cannot read' in str(error.value)


def test_landmark_rejects_booleans_and_bad_psi():
    with pytest.raises(ValueError):
        landmark_from_values([True, 0.0, 0.1, 1.0, 0.0])
    with pytest.raises(ValueError):
        landmark_from_values([0.1, 0.0, 0.1, 1.0, 4.0])


# --- landmark_file kinds (finding 6: a directory was renamed silently) ---------------

def test_a_directory_as_landmark_file_is_refused_by_name(tmp_path):
    link = tmp_path / 'landmarks.yaml'
    link.mkdir()
    with pytest.raises(LandmarkFileError) as error:
        open_mission_file(str(link))
    assert str(link) in str(error.value) and 'is a directory' in str(error.value)
    assert link.is_dir() and sorted(p.name for p in tmp_path.iterdir()) == ['landmarks.yaml']
    with pytest.raises(LandmarkFileError, match='is a directory, not a regular file'):
        load_landmarks(str(link))


@pytest.mark.parametrize('kind', ['directory', 'fifo', 'loop'])
def test_a_symlink_to_what_is_not_a_regular_file_is_refused(tmp_path, kind):
    link = tmp_path / 'landmarks.yaml'
    if kind == 'directory':
        (tmp_path / 'target').mkdir()
        os.symlink('target', str(link))
    elif kind == 'fifo':
        os.mkfifo(str(tmp_path / 'target'))
        os.symlink('target', str(link))
    else:
        os.symlink('landmarks.yaml', str(link))
    with pytest.raises(LandmarkFileError) as error:
        open_mission_file(str(link), mission='m')
    assert str(link) in str(error.value) and 'refusing' in str(error.value)


def test_a_dangling_symlink_is_replaced(tmp_path):
    link = tmp_path / 'landmarks.yaml'
    os.symlink('gone.yaml', str(link))
    writer = open_mission_file(str(link), mission='m', fsync=False)
    writer.append(PATH[0])
    writer.close()
    assert load_landmarks(str(link)).landmarks == PATH[:1]


def test_the_writer_never_writes_through_a_planted_symlink(tmp_path):
    victim = tmp_path / 'victim'
    victim.write_text('precious\n')
    os.symlink(str(victim), str(tmp_path / 'lm.yaml'))
    with pytest.raises(FileExistsError):
        LandmarkWriter(str(tmp_path / 'lm.yaml'))
    assert victim.read_text() == 'precious\n'


# --- write failures (finding 6: ENOSPC tracebacks, the loss not reported) -------------

class FailingDisk(object):
    """Makes os.write / os.fsync / os.ftruncate fail for one file descriptor."""

    def __init__(self, monkeypatch, fd):
        self.fd = fd
        self.write_error = self.fsync_error = self.truncate_error = None
        self.partial = 0            # bytes written before a write fails
        real_write, real_fsync, real_truncate = os.write, os.fsync, os.ftruncate

        def write(fd, data):
            if fd == self.fd and self.write_error:
                if self.partial:
                    real_write(fd, bytes(data[:self.partial]))
                raise OSError(self.write_error, os.strerror(self.write_error))
            return real_write(fd, data)

        def fsync(fd):
            if fd == self.fd and self.fsync_error:
                raise OSError(self.fsync_error, os.strerror(self.fsync_error))
            return real_fsync(fd)

        def ftruncate(fd, size):
            if fd == self.fd and self.truncate_error:
                raise OSError(self.truncate_error, os.strerror(self.truncate_error))
            return real_truncate(fd, size)

        monkeypatch.setattr(os, 'write', write)
        monkeypatch.setattr(os, 'fsync', fsync)
        monkeypatch.setattr(os, 'ftruncate', ftruncate)


def test_enospc_is_one_clear_error_and_leaves_whole_lines(tmp_path, monkeypatch):
    path = str(tmp_path / 'lm.yaml')
    writer = LandmarkWriter(path)
    writer.append(PATH[0])
    disk = FailingDisk(monkeypatch, writer._fd)
    disk.write_error, disk.partial = errno.ENOSPC, 20          # a half line reaches the file
    with pytest.raises(StorageError) as error:
        writer.append(PATH[1])
    message = str(error.value)
    assert message == ('cannot append landmark_000002 to %s: No space left on device (ENOSPC); '
                       '1 record lost' % path)
    assert error.value.errno == errno.ENOSPC and error.value.lost == 1 == writer.lost
    assert open(path).read().endswith('\n')                    # the half line was cut off
    with pytest.raises(StorageError, match='2 records lost'):
        writer.append(PATH[2])
    disk.write_error = None                                    # space freed
    assert writer.append(PATH[3]) == 'landmark_000004'
    writer.close()
    loaded = load_landmarks(path)
    assert loaded.landmarks == [PATH[0], PATH[3]] and writer.count == 2
    assert loaded.missing == 2
    assert loaded.gaps == [Gap('landmark_000004', 'landmark_000002 to landmark_000003 lost '
                                                  '(not written)')]


def test_lost_after_end_tells_a_lost_tail_from_holes(tmp_path, monkeypatch):
    # finding 6 (a full disk that stays full): the landmarks lost after the file's last one
    # are the end of the path, where the way back starts; holes are bridged by the return
    path = str(tmp_path / 'lm.yaml')
    writer = LandmarkWriter(path)
    writer.append(PATH[0])
    disk = FailingDisk(monkeypatch, writer._fd)
    disk.write_error = errno.ENOSPC
    for landmark in PATH[1:3]:
        with pytest.raises(StorageError):
            writer.append(landmark)
    disk.write_error = None
    writer.append(PATH[3])                                     # a hole of 2, then written again
    disk.write_error = errno.ENOSPC
    with pytest.raises(StorageError):
        writer.append(PATH[0])                                 # and the end lost
    writer.close()
    loaded = load_landmarks(path)
    assert (loaded.missing, writer.lost) == (2, 3)
    assert loaded.lost_after_end(writer.lost) == 1
    assert loaded.lost_after_end(2) == 0 and loaded.lost_after_end(0) == 0
    for bad in (-1, 1.5, True, None):
        with pytest.raises(ValueError, match='reported_lost must be a count'):
            loaded.lost_after_end(bad)


def test_the_writer_sums_what_the_lost_landmarks_covered(tmp_path, monkeypatch):
    # a return bridges a loss only when the robot stood still (core/return_plan.still_loss):
    # the writer knows the d of each landmark it could not write, and its heading change
    path = str(tmp_path / 'lm.yaml')
    writer = LandmarkWriter(path, fsync=False)
    disk = FailingDisk(monkeypatch, None)
    disk.fd, disk.write_error = writer._fd, errno.ENOSPC
    with pytest.raises(StorageError):
        writer.append(PATH[0])              # the first: its turn is |w| T (no psi before it)
    disk.write_error = None
    writer.append(PATH[1])
    disk.write_error = errno.ENOSPC
    for landmark in PATH[2:]:
        with pytest.raises(StorageError):
            writer.append(landmark)
    assert writer.lost == 3
    assert writer.lost_distance == pytest.approx(PATH[0].d + PATH[2].d + PATH[3].d)
    turns = [abs(PATH[0].w) * PATH[0].T, abs(-3.1 - 0.061 + 2 * math.pi), abs(-3.14159 + 3.1)]
    assert writer.lost_turn == pytest.approx(sum(turns))
    writer.close()
    resumed = LandmarkWriter.resume(path, fsync=False)      # a restart: counts afresh, psi kept
    assert (resumed.lost, resumed.lost_distance, resumed.lost_turn) == (0, 0.0, 0.0)
    disk.fd, disk.write_error = resumed._fd, errno.ENOSPC
    with pytest.raises(StorageError):
        resumed.append(PATH[1])             # the same heading as the file's last landmark
    assert (resumed.lost, resumed.lost_turn) == (1, 0.0)
    resumed.close()


def test_a_storage_that_cannot_hold_a_file_leaves_the_symlink_as_it_was(tmp_path, monkeypatch):
    # a full disk at start: the new mission file is not made, landmark_file still points at
    # the earlier mission's (or is missing), never at nothing
    link = str(tmp_path / 'landmarks.yaml')
    real_write = os.write

    def full(fd, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(os, 'write', full)
    with pytest.raises(StorageError, match=r'cannot create .*landmarks-.*\.yaml: No space left '
                                           r'on device \(ENOSPC\)'):
        open_mission_file(link, mission='m1', fsync=False)
    assert os.listdir(str(tmp_path)) == []
    monkeypatch.setattr(os, 'write', real_write)
    first = open_mission_file(link, mission='m1', fsync=False)
    first.append(PATH[0])
    first.close()
    monkeypatch.setattr(os, 'write', full)
    with pytest.raises(StorageError):
        open_mission_file(link, mission='m2', fsync=False, when=datetime.datetime(2030, 1, 1))
    assert os.path.realpath(link) == first.path and load_landmarks(link).landmarks == PATH[:1]
    assert sorted(os.listdir(str(tmp_path))) == sorted(['landmarks.yaml', os.path.basename(first.path)])


def test_a_failed_fsync_removes_the_line(tmp_path, monkeypatch):
    path = str(tmp_path / 'lm.yaml')
    writer = LandmarkWriter(path)
    writer.append(PATH[0])
    size = os.path.getsize(path)
    disk = FailingDisk(monkeypatch, writer._fd)
    disk.fsync_error = errno.EIO
    with pytest.raises(StorageError, match=r'Input/output error \(EIO\); 1 record lost'):
        writer.append(PATH[1])
    assert os.path.getsize(path) == size == writer.bytes


def test_a_writer_that_cannot_cut_a_half_line_keeps_failing_cleanly(tmp_path, monkeypatch):
    path = str(tmp_path / 'lm.yaml')
    writer = LandmarkWriter(path)
    writer.append(PATH[0])
    disk = FailingDisk(monkeypatch, writer._fd)
    disk.write_error, disk.partial, disk.truncate_error = errno.EIO, 30, errno.EIO
    for lost in (1, 2):
        with pytest.raises(StorageError, match='%d records? lost' % lost):
            writer.append(PATH[1])
    disk.write_error = None             # writes work again, but the half line is still there
    with pytest.raises(StorageError, match='3 records lost'):
        writer.append(PATH[2])
    disk.truncate_error = None
    assert writer.append(PATH[3]) == 'landmark_000005'
    writer.close()
    loaded = load_landmarks(path)
    assert loaded.landmarks == [PATH[0], PATH[3]] and loaded.warnings[-1].endswith(
        'landmark_000002 to landmark_000004 lost (not written)')


def test_a_really_full_disk(tiny_tmpfs):
    path = str(tiny_tmpfs / 'lm.yaml')
    writer = LandmarkWriter(path)
    errors = []
    for _ in range(3000):
        try:
            writer.append(PATH[0])
        except StorageError as error:
            errors.append(error)
            if len(errors) == 3:
                break
    writer.close()
    assert len(errors) == 3 and writer.lost == 3
    assert all('No space left on device (ENOSPC)' in str(e) for e in errors)
    loaded = load_landmarks(path)
    assert len(loaded.landmarks) == writer.count > 100
    # the lost ones were the last: no hole before a landmark (the writer reported them)
    assert loaded.gaps == [] and loaded.missing == 0 and open(path).read().endswith('\n')


# --- a restarted recorder continues the mission's file (finding 6) --------------------

def test_a_restarted_recorder_continues_the_current_mission(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    writer = open_mission_file(link, mission='mission-1', metadata={'recorder': 'topic'})
    first_file = writer.path
    for landmark in PATH[:3]:
        writer.append(landmark)
    writer.close()                                             # killed: no finish
    with open(first_file, 'a') as stream:
        stream.write(format_entry('landmark_000004', PATH[3])[:20])    # killed mid-line
    resumed = open_mission_file(link, mission='mission-1', metadata={'recorder': 'topic'})
    assert resumed.path == first_file and os.path.realpath(link) == first_file
    assert resumed.resumed.landmarks == 3 and resumed.resumed.dropped == 1
    assert resumed.pending_gap == RESTART_GAP and 'torn' in resumed.resumed.warnings[0]
    assert resumed.resumed.sample is None          # written without sample numbers
    assert resumed.count == 3 and resumed.total_distance == pytest.approx(sum(l.d for l in PATH[:3]))
    assert resumed.append(PATH[1]) == 'landmark_000004'
    resumed.finish()
    loaded = load_landmarks(link)
    assert loaded.landmarks == PATH[:3] + [PATH[1]] and loaded.finished
    assert loaded.gaps == [Gap('landmark_000004', RESTART_GAP)]
    assert loaded.metadata['mission'] == 'mission-1'
    assert {p.name for p in tmp_path.iterdir()} == {'landmarks.yaml', os.path.basename(first_file)}
    # yaml-cpp-style readers see only the landmarks: the extra keys are metadata
    document = yaml.safe_load(open(link).read())
    assert [k for k in document if k.startswith('landmark_')] == loaded.labels


def test_a_finished_recording_is_not_appended_to(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    writer = open_mission_file(link, mission='m', fsync=False)
    writer.append(PATH[0])
    writer.finish()
    again = open_mission_file(link, mission='m', fsync=False)
    assert again.finished and again.path == writer.path
    with pytest.raises(LandmarkFileError, match='finished'):
        again.append(PATH[1])
    assert load_landmarks(link).landmarks == PATH[:1]


@pytest.mark.parametrize('mission', [None, 'mission-2'])
def test_another_mission_or_no_mission_id_starts_a_new_file(tmp_path, mission):
    link = str(tmp_path / 'landmarks.yaml')
    old = open_mission_file(link, mission='mission-1', fsync=False)
    old.append(PATH[0])
    old.close()
    new = open_mission_file(link, mission=mission, fsync=False, when=datetime.datetime(2030, 1, 1))
    assert new.path != old.path and new.resumed is None and os.path.realpath(link) == new.path
    new.append(PATH[1])
    new.close()
    assert load_landmarks(old.path).landmarks == PATH[:1]
    assert load_landmarks(link).landmarks == [PATH[1]]


def test_a_corrupt_file_of_the_current_mission_is_refused_not_replaced(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    writer = open_mission_file(link, mission='m', fsync=False)
    writer.append(PATH[0])
    writer.close()
    with open(writer.path, 'a') as stream:
        stream.write('landmark_000002: {data: [1e6, 0.0, 0.1, 1.0, 0.0]}\n'
                     'landmark_000003: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n')
    with pytest.raises(LandmarkFileError) as error:
        open_mission_file(link, mission='m')
    assert writer.path in str(error.value) and 'landmark_000002' in str(error.value)


def test_d_beyond_what_the_base_can_cover_in_T_refuses_the_file(tmp_path):
    path = tmp_path / 'lm.yaml'
    path.write_text('landmark_000001: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n'
                    'landmark_000002: {data: [0.1, 0.0, 1000000.0, 2.0, 0.0]}\n')
    with pytest.raises(LandmarkFileError) as error:
        load_landmarks(str(path))
    assert 'landmark_000002' in str(error.value) and 'farther than the base can go' in str(error.value)


# --- which sample each landmark came from, and catching up after a restart -------------

def test_samples_entries_only_where_the_numbering_changes(tmp_path):
    path = str(tmp_path / 'lm.yaml')
    with closing(LandmarkWriter(path)) as writer:
        for seq, landmark in zip((1, 2, 4, 5), PATH):       # sample 3 made no landmark
            writer.append(landmark, SampleMark(12.5, seq))
        writer.append(PATH[0], SampleMark(40.25, 1))         # the publisher restarted
    text = open(path).read()
    assert text.count('samples_') == 3, text
    loaded = load_landmarks(path)
    assert loaded.landmarks == PATH + [PATH[0]] and loaded.gaps == [] and loaded.warnings == []
    assert loaded.sample == SampleMark(40.25, 1)
    assert load_landmarks(path).metadata == {'format': 1, 'fields': ['v', 'w', 'd', 'T', 'psi']}


def test_the_last_sample_counts_lost_labels(tmp_path):
    path = str(tmp_path / 'lm.yaml')
    with closing(LandmarkWriter(path)) as writer:
        writer.append(PATH[0], SampleMark(3.0, 7))
        writer._next_index += 1                              # landmark_000002 lost (sample 8)
        writer.append(PATH[1], SampleMark(3.0, 9))
    assert open(path).read().count('samples_') == 1
    assert load_landmarks(path).sample == SampleMark(3.0, 9)


def test_a_resumed_writer_knows_its_last_sample_and_restores_the_chain(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    writer = open_mission_file(link, mission='m')
    for seq, landmark in enumerate(PATH[:3], 1):
        writer.append(landmark, SampleMark(5.0, seq))
    writer.close()
    resumed = open_mission_file(link, mission='m')
    assert resumed.resumed.sample == resumed.sample == SampleMark(5.0, 3)
    assert resumed.holds(SampleMark(5.0, 3)) and resumed.holds(SampleMark(5.0, 1))
    assert not resumed.holds(SampleMark(5.0, 4)) and not resumed.holds(SampleMark(6.0, 1))
    resumed.chain_restored()                                 # caught up: no gap
    resumed.append(PATH[3], SampleMark(5.0, 4))
    resumed.close()
    loaded = load_landmarks(link)
    assert loaded.gaps == [] and loaded.sample == SampleMark(5.0, 4) and loaded.landmarks == PATH


def test_a_resumed_writer_that_cannot_catch_up_writes_its_gap(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    writer = open_mission_file(link, mission='m')
    writer.append(PATH[0], SampleMark(5.0, 1))
    writer.close()
    resumed = open_mission_file(link, mission='m')
    assert load_landmarks(link).gaps == []                   # nothing written until a landmark
    resumed.append(PATH[1], SampleMark(5.0, 9))
    resumed.close()
    loaded = load_landmarks(link)
    assert loaded.gaps == [Gap('landmark_000002', RESTART_GAP)]
    assert loaded.sample == SampleMark(5.0, 9)


def test_a_samples_entry_left_before_a_torn_line_is_overridden(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    writer = open_mission_file(link, mission='m')
    writer.append(PATH[0], SampleMark(5.0, 1))
    writer.close()
    with open(os.path.realpath(link), 'a') as stream:       # killed mid-write of the next pair
        stream.write("samples_2: {from: landmark_000002, recording: 5.0, sample: 30}\n"
                     + format_entry('landmark_000002', PATH[1])[:15])
    resumed = open_mission_file(link, mission='m')
    assert resumed.sample == SampleMark(5.0, 1)
    resumed.chain_restored()
    resumed.append(PATH[1], SampleMark(5.0, 2))
    resumed.close()
    assert load_landmarks(link).sample == SampleMark(5.0, 2)


@pytest.mark.parametrize('entry', ['samples_1: [1, 2]', 'samples_1: {from: landmark_1, sample: 0, recording: 1.0}',
                                   "samples_1: {from: lm_1, sample: 1, recording: 1.0}",
                                   "samples_1: {from: landmark_1, sample: 1, recording: 'x'}"])
def test_a_bad_samples_entry_is_refused_by_name(tmp_path, entry):
    path = tmp_path / 'lm.yaml'
    path.write_text(entry + '\n' + format_entry('landmark_000001', PATH[0]))
    with pytest.raises(LandmarkFileError) as error:
        load_landmarks(str(path))
    assert 'samples_1' in str(error.value)

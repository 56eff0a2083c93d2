"""Mission files: each mission records into its own time-stamped landmark file, behind the
``landmark_file`` symlink (:func:`open_mission_file`: continued after a restart, else new);
:class:`LandmarkWriter` appends one durable line per landmark; nothing recorded is
overwritten. Format and reader: core/store.py; why: docs/recording.md, "File"."""
import datetime
import os
import stat
from collections import namedtuple

import yaml

from .files import (StorageError, describe_mode, fsync_directory, read_regular_file,
                    remove_quietly, replace_with_symlink, write_all)
from .geometry import wrap_angle
from .landmark import FIELDS
from .store import (FINISHED_KEY, FORMAT_VERSION, MAX_FILE_BYTES, METADATA_KEY, OWN_LINES,
                    LandmarkFileError, flow_line, format_entry, label_for, load_landmarks, parse)

#: Why a restarted recorder's first landmark breaks the d chain.
RESTART_GAP = ('the recorder restarted mid-mission: this landmark measures d from where the robot '
               'was at the restart, not from the previous landmark')

ResumeInfo = namedtuple('ResumeInfo', 'landmarks dropped warnings sample')
ResumeInfo.__doc__ = 'What :meth:`LandmarkWriter.resume` found (``sample``: the last SampleMark).'


class LandmarkWriter(object):
    """Creates a mission file (FileExistsError if it exists; :meth:`resume` continues one): ``count``,
    ``lost``, ``lost_distance``, ``lost_turn``, ``bytes``, ``total_distance``, ``sample``, ``pending_gap``."""

    def __init__(self, path, metadata=None, fsync=True):
        self._setup(path, fsync)
        flags = (os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_APPEND
                 | getattr(os, 'O_CLOEXEC', 0))
        try:
            os.makedirs(os.path.dirname(self.path), exist_ok=True)
            self._fd = os.open(self.path, flags, 0o666)
        except FileExistsError:
            raise
        except OSError as error:
            raise StorageError(self.path, error, 'create')
        header = {'format': FORMAT_VERSION, 'fields': list(FIELDS), **(metadata or {})}
        try:
            self._write_line('# blind_navigation path landmarks [v, w, d, T, psi] '
                             '(m/s, rad/s, m, s, rad; d from the previous landmark)\n'
                             + flow_line(METADATA_KEY, header))
            fsync_directory(os.path.dirname(self.path))
        except OSError as error:
            self.close()
            remove_quietly(self.path)
            raise StorageError(self.path, error, 'create')

    def _setup(self, path, fsync):
        self.path, self.fsync = os.path.abspath(path), fsync
        self.count = self.lost = self.bytes = self._gaps = self._samples_entries = 0
        self.lost_distance = self.lost_turn = self.total_distance = 0.0
        self._psi = None            # psi of the last landmark appended, written or lost
        self.finished, self._damaged = False, False
        self.resumed = self._fd = self.sample = self.pending_gap = None
        self._next_index = 1
        self._offset = None         # (recording, seq - label index) the last samples_ entry set

    @classmethod
    def resume(cls, path, fsync=True):
        """Continue ``path`` (validated, torn tail cut, a RESTART_GAP pending; a finished file is
        not reopened)."""
        writer = cls.__new__(cls)
        writer._setup(path, fsync)
        loaded = load_landmarks(writer.path, allow_empty=True, follow_symlinks=False)
        writer.count, writer.total_distance = len(loaded.landmarks), loaded.total_distance
        writer._psi = loaded.landmarks[-1].psi if loaded.landmarks else None
        writer._next_index, writer._gaps = loaded.last_index + 1, loaded.gap_entries
        writer._samples_entries, writer.bytes = loaded.samples_entries, loaded.intact_bytes
        writer.sample = loaded.sample   # the next landmark writes a samples_ entry of its own
        writer.resumed = ResumeInfo(writer.count, loaded.dropped, loaded.warnings, loaded.sample)
        if loaded.finished:
            writer.finished = True
            return writer
        try:
            writer._fd = os.open(writer.path, os.O_WRONLY | os.O_APPEND | os.O_NOFOLLOW
                                 | getattr(os, 'O_CLOEXEC', 0))
            info = os.fstat(writer._fd)
            if info.st_size != loaded.size:
                writer.close()
                raise LandmarkFileError(writer.path, 'changed while it was being reopened (%d bytes '
                                        'read, %d now): is another recorder writing it?'
                                        % (loaded.size, info.st_size))
            if loaded.intact_bytes < info.st_size:
                os.ftruncate(writer._fd, loaded.intact_bytes)
        except OSError as error:
            writer.close()
            raise StorageError(writer.path, error, 'reopen')
        writer.pending_gap = RESTART_GAP
        return writer

    def holds(self, sample):
        """True if the SampleMark ``sample`` is in the file already (its recording, not later)."""
        return (sample is not None and self.sample is not None
                and sample.recording == self.sample.recording and sample.seq <= self.sample.seq)

    def chain_restored(self):
        """The next landmark measures ``d`` from the file's last one after all: no gap entry."""
        self.pending_gap = None

    def _gap_line(self, reason):
        key = 'gap_%d' % (self._gaps + 1)
        return key, flow_line(key, {'before': label_for(self._next_index), 'reason': str(reason)})

    def append(self, landmark, sample=None):
        """Write ``landmark`` (at SampleMark ``sample``) with the gap and ``samples_`` entries it
        needs in one write; its label. StorageError: lost (its d and heading change counted)."""
        label = label_for(self._next_index)
        self._check_open('append %s' % label)
        lines, gap_key = [], None
        if self.pending_gap is not None:
            gap_key, line = self._gap_line(self.pending_gap)
            lines.append(line)
        offset = self._offset if sample is None else (sample.recording, sample.seq - self._next_index)
        if offset != self._offset:
            lines.append(flow_line('samples_%d' % (self._samples_entries + 1), {
                'from': label, 'recording': float(sample.recording), 'sample': int(sample.seq)}))
        lines.append(format_entry(label, landmark))
        self._next_index += 1
        turn = (abs(wrap_angle(landmark.psi - self._psi)) if self._psi is not None
                else abs(landmark.w) * landmark.T)
        self._psi = landmark.psi
        try:
            self._write_line(''.join(lines))
        except OSError as error:
            self.lost += 1
            self.lost_distance += landmark.d
            self.lost_turn += turn
            raise StorageError(self.path, error, 'append %s to' % label, lost=self.lost)
        if gap_key is not None:
            self._gaps += 1
            self.pending_gap = None
        if offset != self._offset:
            self._samples_entries += 1
            self._offset = offset
        self.sample = sample
        self.count += 1
        self.total_distance += landmark.d
        return label

    def note_gap(self, reason):
        """Write a gap entry before the next landmark; its key. StorageError on failure."""
        self._check_open('note a gap')
        key, line = self._gap_line(reason)
        try:
            self._write_line(line)
        except OSError as error:
            raise StorageError(self.path, error, 'write %s to' % key, lost=self.lost)
        self._gaps += 1
        return key

    def finish(self):
        """Mark the recording finished and close (StorageError if the mark is not written)."""
        self._check_open('finish')
        try:
            self._write_line(flow_line(FINISHED_KEY, {'landmarks': self.count, 'lost': self.lost}))
        except OSError as error:
            raise StorageError(self.path, error, 'mark finished', lost=self.lost)
        finally:
            self.finished = True
            self.close()

    def _check_open(self, action):
        if self.finished:
            raise LandmarkFileError(self.path, 'cannot %s: the recording of this file has '
                                    'finished' % action)
        if self._fd is None:
            raise LandmarkFileError(self.path, 'cannot %s: the writer is closed' % action)

    def _write_line(self, text):
        """Write whole lines; on failure cut the file back to its last whole line."""
        data = text.encode('utf-8')
        if self._damaged:           # an earlier failure could not be cut off: retry first
            os.ftruncate(self._fd, self.bytes)
            self._damaged = False
        try:
            write_all(self._fd, data)
            if self.fsync:
                os.fsync(self._fd)
        except OSError:
            try:
                os.ftruncate(self._fd, self.bytes)
            except OSError:
                self._damaged = True
            raise
        self.bytes += len(data)

    def close(self):
        if self._fd is not None:
            fd, self._fd = self._fd, None
            try:
                os.close(fd)
            except OSError:
                pass


def next_mission_id(current):
    """The id after ``current`` (a launch's id, None, or one made here): ``<launch id>#<n>``."""
    launch, _, number = (current or '').rpartition('#')
    if launch and number.isdigit():
        return '%s#%d' % (launch, int(number) + 1)
    return '%s#2' % (current or 'mission')


def mission_number(current):
    """The number of mission ``current`` within its launch (1: the launch's own id)."""
    _, _, number = (current or '').rpartition('#')
    return int(number) if number.isdigit() else 1


def mission_file_name(landmark_file, when=None):
    """The time-stamped file a mission started at ``when`` records into."""
    when = when or datetime.datetime.now()
    stem, ext = os.path.splitext(landmark_file)
    return '%s-%s%s' % (stem, when.strftime('%Y%m%d-%H%M%S'), ext or '.yaml')


def inspect_landmark_file(landmark_file):
    """'missing', 'regular' (an old layout), 'symlink' (to a regular file), 'dangling', else an error."""
    mode = _mode(os.lstat, landmark_file, 'cannot inspect: %s')
    if mode is None:
        return 'missing'
    if stat.S_ISREG(mode):
        return 'regular'
    if not stat.S_ISLNK(mode):
        raise LandmarkFileError(landmark_file, 'is %s, not a regular file or a symlink to one; '
                                'refusing to use it (move it away or set another landmark_file)'
                                % describe_mode(mode))
    target_mode = _mode(os.stat, landmark_file,
                        'is a symlink that cannot be followed: %s; refusing to use it')
    if target_mode is None:
        return 'dangling'
    if not stat.S_ISREG(target_mode):
        raise LandmarkFileError(landmark_file, 'is a symlink to %s (%s), not to a regular file; '
                                'refusing to use it' % (describe_mode(target_mode),
                                                        os.path.realpath(landmark_file)))
    return 'symlink'


def _mode(stat_call, landmark_file, problem):
    """``stat_call(landmark_file).st_mode``, None if nothing is there (else LandmarkFileError)."""
    try:
        return stat_call(landmark_file).st_mode
    except FileNotFoundError:
        return None
    except OSError as error:
        raise LandmarkFileError(landmark_file, problem % (error.strerror or error))


def read_mission(path):
    """The ``mission`` id in the header of the landmark file ``path``, or None."""
    try:
        text = read_regular_file(path, MAX_FILE_BYTES).decode('utf-8')
    except (OSError, UnicodeDecodeError):
        return None
    for line in text.splitlines():
        if line.startswith(METADATA_KEY + ':'):
            try:
                header = (parse(line) or {}).get(METADATA_KEY)
            except yaml.YAMLError:
                return None
            mission = header.get('mission') if isinstance(header, dict) else None
            return mission if isinstance(mission, str) else None
        if line.startswith(OWN_LINES):
            return None
    return None


def open_mission_file(landmark_file, mission=None, metadata=None, fsync=True, when=None):
    """The writer of the current mission: the file ``landmark_file`` points at if its header carries
    this ``mission`` id (resumed), else a new one, pointed at once it holds its header (an old
    layout's regular file there archived)."""
    if mission is not None and not (isinstance(mission, str) and mission.strip()):
        raise ValueError('mission must be a non-empty string or None, got %r' % (mission,))
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    if inspect_landmark_file(landmark_file) == 'symlink' and mission is not None:
        target = os.path.realpath(landmark_file)
        if read_mission(target) == mission:
            return LandmarkWriter.resume(target, fsync)
    header = dict(metadata or {})
    if mission is not None:
        header['mission'] = mission
    os.makedirs(os.path.dirname(landmark_file), exist_ok=True)
    writer = LandmarkWriter(_unused(mission_file_name(landmark_file, when)), header, fsync)
    try:
        if inspect_landmark_file(landmark_file) == 'regular':
            mtime = datetime.datetime.fromtimestamp(os.path.getmtime(landmark_file))
            os.rename(landmark_file, _unused(mission_file_name(landmark_file, mtime)))
        replace_with_symlink(landmark_file, os.path.basename(writer.path))
    except OSError as error:
        writer.close()
        remove_quietly(writer.path)
        raise StorageError(landmark_file, error, 'make a symlink to %s at'
                           % os.path.basename(writer.path))
    return writer


def _unused(path):
    """``path``, or ``path`` with a -N suffix if that name is already taken."""
    stem, ext = os.path.splitext(path)
    candidate, n = path, 1
    while os.path.lexists(candidate):
        candidate = '%s-%d%s' % (stem, n, ext)
        n += 1
    return candidate

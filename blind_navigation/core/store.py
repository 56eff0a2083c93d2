"""The YAML landmark store: one line per path landmark, written incrementally.

Format (see INTERFACE.md), readable by PyYAML and by yaml-cpp::

    # comment lines
    blind_navigation: {format: 1, fields: [v, w, d, T, psi], mission: '...', ...}
    samples_1: {from: landmark_000001, recording: 12.34, sample: 1}
    landmark_000001: {data: [0.0861, 0.0012, 0.1718, 2.0, 0.0131]}
    landmark_000002: {data: [0.0859, 0.0964, 0.0862, 1.0, 0.061]}
    gap_1: {before: landmark_000003, reason: '...'}
    landmark_000003: {data: [0.0901, 0.0, 0.1802, 2.0, 0.0608]}
    finished: {landmarks: 3, lost: 0}

:class:`LandmarkWriter` appends one durable line per landmark (a failed write
raises core/files.StorageError and leaves whole lines); :func:`load_landmarks`
reads a file back with its gaps (:class:`LoadedPath`); :func:`open_mission_file`
continues the current mission's file or starts a new time-stamped one behind
the ``landmark_file`` symlink. Why lines, gaps, sample marks and mission
files: docs/recording.md, "File".
"""
import datetime
import os
import re
import stat
from collections import namedtuple

import yaml

from .files import (FileContentError, NotRegularFileError, StorageError, describe_mode,
                    fsync_directory, read_regular_file, replace_with_symlink, write_all)
from .landmark import FIELDS, Limits, landmark_from_values

LABEL_PREFIX = 'landmark_'
LABEL_RE = re.compile(r'^landmark_(\d+)$')
GAP_RE = re.compile(r'^gap_(\d+)$')
SAMPLES_RE = re.compile(r'^samples_(\d+)$')
METADATA_KEY = 'blind_navigation'
FINISHED_KEY = 'finished'
FORMAT_VERSION = 1
#: Largest landmark file read (about 300 hours of recording at 1 landmark/s).
MAX_FILE_BYTES = 64 << 20
#: Kinds of entry line the writer makes (a torn one is dropped on load).
_OWN_LINES = (LABEL_PREFIX, 'gap_', 'samples_', FINISHED_KEY + ':')
#: Why a restarted recorder's first landmark breaks the d chain.
RESTART_GAP = ('the recorder restarted mid-mission: this landmark measures d from where the robot '
               'was at the restart, not from the previous landmark')


class LandmarkFileError(FileContentError):
    """A landmark file that cannot be used; the message names the file and entry."""

    def __init__(self, path, reason, entry=None):
        super(LandmarkFileError, self).__init__(path, entry, reason)
        self.entry = entry


def label_for(index):
    """The unique, ordered key of the ``index``-th landmark (1-based)."""
    return '%s%06d' % (LABEL_PREFIX, index)


def format_number(value):
    """Compact text for one float (six significant digits) that YAML 1.1 reads as
    a float: PyYAML needs a '.' in the mantissa ('1e-05' would be a string)."""
    mantissa, e, exponent = ('%.6g' % value).partition('e')
    if '.' not in mantissa:
        mantissa += '.0'
    return mantissa + e + exponent


def format_entry(label, landmark):
    """One line of the store for ``landmark`` under ``label``."""
    return '%s: {data: [%s]}\n' % (label, ', '.join(format_number(v) for v in landmark))


def _flow_line(key, value):
    """``key: {...}`` on one line (YAML flow style)."""
    return '%s: %s' % (key, yaml.safe_dump(value, default_flow_style=True, width=1 << 30))


Gap = namedtuple('Gap', 'before reason')
Gap.__doc__ = ('A break in the d chain: ``before`` is the label of the first landmark after it '
               '(its d does not start at the previous landmark), ``reason`` says why.')

SampleMark = namedtuple('SampleMark', 'recording seq')
SampleMark.__doc__ = ('A sample of the sampling publisher: its ``recording`` (the time the recording '
                      'started, s) and its number ``seq`` in it (1, 2, ...).')

ResumeInfo = namedtuple('ResumeInfo', 'landmarks dropped warnings sample')
ResumeInfo.__doc__ = ('What :meth:`LandmarkWriter.resume` found: ``landmarks`` already in the '
                      'file, ``dropped`` torn entries cut off, ``warnings`` (text), ``sample`` (the '
                      ':class:`SampleMark` of the last landmark, or None if the file does not say).')


class LandmarkWriter(object):
    """Appends landmarks to a mission file, one durable line each; see the module docstring.

    ``LandmarkWriter(path, metadata, fsync)`` creates a new file (it must not
    exist: an earlier mission is never overwritten; FileExistsError);
    :meth:`resume` continues an existing one. Attributes: ``path``, ``count``
    (landmarks in the file), ``lost`` (appends that failed), ``total_distance``
    (sum of d in the file, m), ``bytes``, ``finished``, ``resumed`` (a
    :class:`ResumeInfo`, or None for a new file), ``sample`` (the
    :class:`SampleMark` of the last landmark, when known), ``pending_gap`` (the
    reason of a gap entry to write before the next landmark, or None).
    """

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
        header = {'format': FORMAT_VERSION, 'fields': list(FIELDS)}
        header.update(metadata or {})
        try:
            self._write_line('# blind_navigation path landmarks [v, w, d, T, psi] '
                             '(m/s, rad/s, m, s, rad; d from the previous landmark)\n'
                             + _flow_line(METADATA_KEY, header))
            fsync_directory(os.path.dirname(self.path))
        except OSError as error:
            self.close()
            try:
                os.unlink(self.path)
            except OSError:
                pass
            raise StorageError(self.path, error, 'create')

    def _setup(self, path, fsync):
        self.path = os.path.abspath(path)
        self.fsync = fsync
        self.count = 0
        self.lost = 0
        self.total_distance = 0.0
        self.finished = False
        self.resumed = None
        self._fd = None
        self._size = 0
        self._next_index = 1
        self._gaps = 0
        self._samples_entries = 0
        self._offset = None         # (recording, seq - label index) the last samples_ entry set
        self.sample = None
        self.pending_gap = None
        self._damaged = False

    @classmethod
    def resume(cls, path, fsync=True, limits=Limits(), reason='the recorder restarted'):
        """Continue the mission file ``path`` (a regular file, not a symlink).

        The file is validated (:func:`load_landmarks`; a bad entry raises
        LandmarkFileError); a torn last entry is cut off (counted in
        ``resumed.dropped`` and warned about); labels continue after the last
        one; a ``gap_<n>`` entry (``reason``) is pending (``pending_gap``: written
        before the next landmark), since the next landmark cannot measure ``d``
        from the last one, unless the caller restores the chain first
        (:meth:`chain_restored`). A finished file is not reopened: the writer
        is ``finished`` and refuses appends.
        """
        writer = cls.__new__(cls)
        writer._setup(path, fsync)
        loaded = load_landmarks(writer.path, limits, allow_empty=True, follow_symlinks=False)
        writer.count = len(loaded.landmarks)
        writer.total_distance = loaded.total_distance
        writer._next_index = loaded.last_index + 1
        writer._gaps = loaded.gap_entries
        writer._samples_entries = loaded.samples_entries
        writer._size = loaded.intact_bytes
        writer.sample = loaded.sample   # the next landmark writes a samples_ entry of its own:
                                        # one a killed writer left before a torn line may be wrong
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
        writer.pending_gap = str(reason)
        return writer

    @property
    def bytes(self):
        """Size of the file so far (whole lines only), bytes."""
        return self._size

    @property
    def next_label(self):
        """The label the next landmark will get."""
        return label_for(self._next_index)

    def holds(self, sample):
        """True if ``sample`` (a :class:`SampleMark`) is in the file already: the same
        recording as the last landmark's sample and not after it."""
        return (sample is not None and self.sample is not None
                and sample.recording == self.sample.recording and sample.seq <= self.sample.seq)

    def chain_restored(self):
        """The caller's next landmark measures ``d`` from the file's last one after
        all: no gap entry is written (see :meth:`resume`)."""
        self.pending_gap = None

    def append(self, landmark, sample=None):
        """Write ``landmark`` (taken at ``sample``, a :class:`SampleMark`, if known)
        durably, after the pending gap entry and the ``samples_`` entry it needs, in
        one write; return its label. StorageError if the write fails (the label is
        used up, ``lost`` counts it; the entries before it are written with the next)."""
        label = self.next_label
        self._check_open('append %s' % label)
        self._next_index += 1
        lines, gap_key, offset = [], None, self._offset
        if self.pending_gap is not None:
            gap_key = 'gap_%d' % (self._gaps + 1)
            lines.append(_flow_line(gap_key, {'before': label, 'reason': self.pending_gap}))
        if sample is not None and (sample.recording, sample.seq - (self._next_index - 1)) != offset:
            offset = (sample.recording, sample.seq - (self._next_index - 1))
            lines.append(_flow_line('samples_%d' % (self._samples_entries + 1), {
                'from': label, 'recording': float(sample.recording), 'sample': int(sample.seq)}))
        lines.append(format_entry(label, landmark))
        try:
            self._write_line(''.join(lines))
        except OSError as error:
            self.lost += 1
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
        """Write a gap entry before the next landmark (its ``d`` will not start at
        the previous landmark); return the entry's key. StorageError on failure."""
        self._check_open('note a gap')
        key = 'gap_%d' % (self._gaps + 1)
        try:
            self._write_line(_flow_line(key, {'before': self.next_label, 'reason': str(reason)}))
        except OSError as error:
            raise StorageError(self.path, error, 'write %s to' % key, lost=self.lost)
        self._gaps += 1
        return key

    def finish(self):
        """Mark the recording finished (a later :meth:`resume` will not append)
        and close. StorageError if the mark cannot be written (still closed)."""
        self._check_open('finish')
        try:
            self._write_line(_flow_line(FINISHED_KEY, {'landmarks': self.count, 'lost': self.lost}))
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
            os.ftruncate(self._fd, self._size)
            self._damaged = False
        try:
            write_all(self._fd, data)
            if self.fsync:
                os.fsync(self._fd)
        except OSError:
            try:
                os.ftruncate(self._fd, self._size)
            except OSError:
                self._damaged = True
            raise
        self._size += len(data)

    def close(self):
        if self._fd is not None:
            fd, self._fd = self._fd, None
            try:
                os.close(fd)
            except OSError:
                pass

    def __enter__(self):
        return self

    def __exit__(self, *_exc):
        self.close()


class LoadedPath(object):
    """What :func:`load_landmarks` read: landmarks in recording order, their
    labels, the header map (may be empty), ``warnings`` (e.g. a dropped torn
    entry), ``gaps`` (:class:`Gap` list: breaks of the d chain and landmarks
    lost to write failures), ``finished`` (the recorder marked the end),
    ``dropped`` (torn entries dropped), ``size`` and ``intact_bytes`` (file
    bytes, and those before a dropped torn entry), ``sample`` (the
    :class:`SampleMark` of the last label, from the ``samples_`` entries, or None)."""

    def __init__(self, path, landmarks, labels, metadata, warnings, **details):
        self.path = path
        self.landmarks = landmarks
        self.labels = labels
        self.metadata = metadata
        self.warnings = warnings
        self.gaps = details.get('gaps', [])
        self.finished = details.get('finished', False)
        self.dropped = details.get('dropped', 0)
        self.size = details.get('size', 0)
        self.intact_bytes = details.get('intact_bytes', 0)
        self.last_index = details.get('last_index', 0)
        self.gap_entries = details.get('gap_entries', 0)
        self.samples_entries = details.get('samples_entries', 0)
        self.sample = details.get('sample')

    @property
    def total_distance(self):
        return sum(landmark.d for landmark in self.landmarks)

    @property
    def total_duration(self):
        return sum(landmark.T for landmark in self.landmarks)

    @property
    def missing(self):
        """Landmarks lost to write failures (holes in the label numbering)."""
        return self.last_index - len(self.landmarks) if self.landmarks else 0

    def lost_after_end(self, reported_lost):
        """Of the ``reported_lost`` landmarks the recorder could not write (its count,
        blind_navigation/StorageUsage.lost), those after this file's last landmark: not
        holes in the numbering, which a return bridges, but the end of the recorded
        path, where the way back starts (e.g. the disk filled up and stayed full)."""
        if isinstance(reported_lost, bool) or not isinstance(reported_lost, int) or reported_lost < 0:
            raise ValueError('reported_lost must be a count >= 0, got %r' % (reported_lost,))
        return max(0, reported_lost - self.missing)


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses duplicate keys instead of keeping the last one."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, 'duplicate key %r' % (key,), key_node.start_mark)
            seen.add(key)
        return super(_UniqueKeyLoader, self).construct_mapping(node, deep)


def _parse(text):
    return yaml.load(text, Loader=_UniqueKeyLoader)


def _drop_torn_tail(path, text, warnings):
    """``text`` without a torn last entry (a killed writer's partial line)."""
    if text and not text.endswith('\n'):
        cut = text.rfind('\n') + 1
        warnings.append('%s: dropped a torn last entry (no end of line): %r' % (path, text[cut:][:80]))
        return text[:cut]
    lines = text.splitlines(True)
    if lines and lines[-1].startswith(_OWN_LINES):
        try:
            _parse(lines[-1])
        except yaml.YAMLError:
            warnings.append('%s: dropped an unparsable last entry: %r' % (path, lines[-1][:80]))
            return ''.join(lines[:-1])
    return text


def _read(path, follow_symlinks):
    try:
        data = read_regular_file(path, MAX_FILE_BYTES, follow_symlinks)
    except NotRegularFileError as error:
        raise LandmarkFileError(path, 'cannot read: is %s, not a regular file' % error.what)
    except OSError as error:
        raise LandmarkFileError(path, 'cannot read: %s' % (error.strerror or error))
    try:
        return data, data.decode('utf-8')
    except UnicodeDecodeError as error:
        raise LandmarkFileError(path, 'not a text file: %s' % error)


def _gap_from(path, key, value):
    if not (isinstance(value, dict) and isinstance(value.get('before'), str)
            and LABEL_RE.match(value['before']) and isinstance(value.get('reason'), str)):
        raise LandmarkFileError(path, 'a gap entry must be {before: landmark_<number>, reason: '
                                '<text>}, got %r' % (value,), key)
    return Gap(value['before'], value['reason'])


def _samples_from(path, key, value):
    """(label index, SampleMark) of a ``samples_<n>`` entry."""
    if isinstance(value, dict) and isinstance(value.get('from'), str):
        match = LABEL_RE.match(value['from'])
        recording, seq = value.get('recording'), value.get('sample')
        if match and isinstance(recording, (int, float)) and not isinstance(recording, bool) \
                and isinstance(seq, int) and not isinstance(seq, bool) and seq >= 1:
            return int(match.group(1)), SampleMark(float(recording), seq)
    raise LandmarkFileError(path, 'a samples entry must be {from: landmark_<number>, recording: '
                            '<s>, sample: <number from 1>}, got %r' % (value,), key)


def _last_sample(marks, last_index):
    """The SampleMark of label ``last_index`` by the ``samples_`` entry for the
    latest label at or before it (of two for one label, the later in the file)."""
    best = None
    for index, mark in marks:
        if index <= last_index and (best is None or index >= best[0]):
            best = (index, mark)
    if best is None or not last_index:
        return None
    return best[1]._replace(seq=best[1].seq + last_index - best[0])


def load_landmarks(path, limits=Limits(), allow_empty=False, follow_symlinks=True):
    """Read and validate a landmark file; raise LandmarkFileError on the first bad entry."""
    data, text = _read(path, follow_symlinks)
    warnings = []
    intact = _drop_torn_tail(path, text, warnings)
    try:
        document = _parse(intact)
    except yaml.YAMLError as error:
        raise LandmarkFileError(path, 'not valid YAML: %s' % str(error).replace('\n', ' '))
    if document is None:
        document = {}
    if not isinstance(document, dict):
        raise LandmarkFileError(path, 'top level must be a map of landmark entries, got %s'
                                % type(document).__name__)
    landmarks, labels, metadata, gaps, gap_entries, marks = [], [], {}, [], 0, []
    previous_index = 0
    for key, value in document.items():
        if isinstance(key, str) and GAP_RE.match(key):
            gaps.append(_gap_from(path, key, value))
            gap_entries += 1
            continue
        if isinstance(key, str) and SAMPLES_RE.match(key):
            marks.append(_samples_from(path, key, value))
            continue
        if not isinstance(key, str) or not key.startswith(LABEL_PREFIX):
            metadata[key] = value
            continue
        match = LABEL_RE.match(key)
        if not match:
            raise LandmarkFileError(path, 'label must be landmark_<number>', key)
        index = int(match.group(1))
        if index <= previous_index:
            raise LandmarkFileError(path, 'labels out of recording order (after %s)'
                                    % label_for(previous_index), key)
        if index > previous_index + 1:
            gaps.append(Gap(key, '%s lost (not written)' % (
                label_for(previous_index + 1) if index == previous_index + 2 else
                '%s to %s' % (label_for(previous_index + 1), label_for(index - 1)))))
        previous_index = index
        if not isinstance(value, dict) or 'data' not in value:
            raise LandmarkFileError(path, 'entry must be a map with a data sequence '
                                    '[v, w, d, T, psi], got %r' % (value,), key)
        try:
            landmarks.append(landmark_from_values(value['data'], limits))
        except ValueError as error:
            raise LandmarkFileError(path, str(error), key)
        labels.append(key)
    if not landmarks and not allow_empty:
        raise LandmarkFileError(path, 'no landmarks in the file (empty path)%s'
                                % ''.join('; ' + warning for warning in warnings))
    gaps.sort(key=lambda gap: gap.before)
    for gap in gaps:
        warnings.append('%s: gap in the recorded path before %s: %s' % (path, gap.before, gap.reason))
    return LoadedPath(path, landmarks, labels, metadata.get(METADATA_KEY, {}) or {}, warnings,
                      gaps=gaps, finished=FINISHED_KEY in metadata,
                      dropped=1 if intact != text else 0, size=len(data),
                      intact_bytes=len(intact.encode('utf-8')), last_index=previous_index,
                      gap_entries=gap_entries, samples_entries=len(marks),
                      sample=_last_sample(marks, previous_index))


# --- mission files -------------------------------------------------------------

def mission_file_name(landmark_file, when=None):
    """The time-stamped file a mission started at ``when`` records into."""
    when = when or datetime.datetime.now()
    stem, ext = os.path.splitext(landmark_file)
    return '%s-%s%s' % (stem, when.strftime('%Y%m%d-%H%M%S'), ext or '.yaml')


def inspect_landmark_file(landmark_file):
    """What the configured ``landmark_file`` name is: ``'missing'``, ``'regular'``
    (an old layout's file), ``'symlink'`` (to a regular file) or ``'dangling'``
    (a symlink to nothing). Anything else (a directory, a FIFO, a symlink to a
    directory or a loop) raises LandmarkFileError naming it."""
    try:
        mode = os.lstat(landmark_file).st_mode
    except FileNotFoundError:
        return 'missing'
    except OSError as error:
        raise LandmarkFileError(landmark_file, 'cannot inspect: %s' % (error.strerror or error))
    if stat.S_ISREG(mode):
        return 'regular'
    if not stat.S_ISLNK(mode):
        raise LandmarkFileError(landmark_file, 'is %s, not a regular file or a symlink to one; '
                                'refusing to use it (move it away or set another landmark_file)'
                                % describe_mode(mode))
    try:
        target_mode = os.stat(landmark_file).st_mode
    except FileNotFoundError:
        return 'dangling'
    except OSError as error:
        raise LandmarkFileError(landmark_file, 'is a symlink that cannot be followed: %s; refusing '
                                'to use it' % (error.strerror or error))
    if not stat.S_ISREG(target_mode):
        raise LandmarkFileError(landmark_file, 'is a symlink to %s (%s), not to a regular file; '
                                'refusing to use it' % (describe_mode(target_mode),
                                                        os.path.realpath(landmark_file)))
    return 'symlink'


def start_mission_file(landmark_file, when=None):
    """Choose a new file for a mission and point ``landmark_file`` at it.

    Returns the new (not yet created) path. An existing regular file at
    ``landmark_file`` is kept by renaming it to a time-stamped name first; an
    existing symlink is replaced atomically (core/files.replace_with_symlink). Anything else at
    ``landmark_file`` is refused (:func:`inspect_landmark_file`). Nothing
    recorded is deleted.
    """
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    directory = os.path.dirname(landmark_file)
    os.makedirs(directory, exist_ok=True)
    if inspect_landmark_file(landmark_file) == 'regular':
        mtime = datetime.datetime.fromtimestamp(os.path.getmtime(landmark_file))
        os.rename(landmark_file, _unused(mission_file_name(landmark_file, mtime)))
    target = _unused(mission_file_name(landmark_file, when))
    replace_with_symlink(landmark_file, os.path.basename(target))
    return target


def read_mission(path):
    """The ``mission`` id in the header of the landmark file ``path``, or None
    (no header, no id, or not readable: then it is not the current mission)."""
    try:
        text = read_regular_file(path, MAX_FILE_BYTES).decode('utf-8')
    except (OSError, UnicodeDecodeError):
        return None
    for line in text.splitlines():
        if line.startswith(METADATA_KEY + ':'):
            try:
                header = (_parse(line) or {}).get(METADATA_KEY)
            except yaml.YAMLError:
                return None
            mission = header.get('mission') if isinstance(header, dict) else None
            return mission if isinstance(mission, str) else None
        if line.startswith(_OWN_LINES):
            return None
    return None


def open_mission_file(landmark_file, mission=None, metadata=None, fsync=True, limits=Limits(),
                      when=None):
    """The :class:`LandmarkWriter` of the current mission.

    Rule: if ``mission`` (a non-empty id of the current mission, the same for
    every node restart within it and new for each mission, e.g. the launch's
    start time) is given, and ``landmark_file`` is a symlink to a file whose
    header carries that same ``mission``, the recorder restarted mid-mission:
    that file is continued (:meth:`LandmarkWriter.resume`: validated, a torn
    last entry cut off, labels continued, a gap entry pending; a finished
    recording is not appended to). Otherwise a new file is started
    (:func:`start_mission_file`) with ``metadata`` and ``mission`` in its
    header. Without a ``mission`` id a file is never continued: appending a
    new mission to an old one would send the return along the old path.

    Raises LandmarkFileError (a ``landmark_file`` that is not a regular file or
    a symlink to one; the current mission's file is corrupt) or StorageError.
    """
    if mission is not None and not (isinstance(mission, str) and mission.strip()):
        raise ValueError('mission must be a non-empty string or None, got %r' % (mission,))
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    if inspect_landmark_file(landmark_file) == 'symlink' and mission is not None:
        target = os.path.realpath(landmark_file)
        if read_mission(target) == mission:
            return LandmarkWriter.resume(target, fsync, limits, reason=RESTART_GAP)
    header = dict(metadata or {})
    if mission is not None:
        header['mission'] = mission
    return LandmarkWriter(start_mission_file(landmark_file, when), header, fsync)


def _unused(path):
    """``path``, or ``path`` with a -N suffix if that name is already taken."""
    stem, ext = os.path.splitext(path)
    candidate, n = path, 1
    while os.path.lexists(candidate):
        candidate = '%s-%d%s' % (stem, n, ext)
        n += 1
    return candidate

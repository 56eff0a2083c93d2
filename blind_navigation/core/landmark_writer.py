"""The landmark store's writer: one durable line per landmark in a mission file.

:class:`LandmarkWriter` creates a new file (its header first) or resumes an
existing one (validated by core/store.load_landmarks, a torn tail cut off, a
gap pending), and appends each landmark with the gap and ``samples_`` entries it
needs in one write; a failed write raises core/files.StorageError and leaves
whole lines. Format: core/landmark_format.py; why: docs/recording.md, "File".
"""
import os
from collections import namedtuple

from .files import StorageError, fsync_directory, write_all
from .geometry import wrap_angle
from .landmark import FIELDS, Limits
from .landmark_format import (FINISHED_KEY, FORMAT_VERSION, METADATA_KEY, LandmarkFileError,
                              flow_line, format_entry, label_for)
from .store import load_landmarks

ResumeInfo = namedtuple('ResumeInfo', 'landmarks dropped warnings sample')
ResumeInfo.__doc__ = ('What :meth:`LandmarkWriter.resume` found: ``landmarks`` already in the '
                      'file, ``dropped`` torn entries cut off, ``warnings`` (text), ``sample`` (the '
                      ':class:`SampleMark` of the last landmark, or None if the file does not say).')


class LandmarkWriter(object):
    """Appends landmarks to a mission file, one durable line each; see the module docstring.

    ``LandmarkWriter(path, metadata, fsync)`` creates a new file (it must not
    exist: an earlier mission is never overwritten; FileExistsError);
    :meth:`resume` continues an existing one. Attributes: ``path``, ``count``
    (landmarks in the file), ``lost`` (appends that failed), ``lost_distance``
    and ``lost_turn`` (what the lost landmarks covered: the sum of their d, m, and
    of their heading changes, rad: :meth:`append`), ``total_distance`` (sum of d
    in the file, m), ``bytes``, ``finished``, ``resumed`` (a
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
                             + flow_line(METADATA_KEY, header))
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
        self.lost_distance = 0.0
        self.lost_turn = 0.0
        self._psi = None            # psi of the last landmark appended, written or lost
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
        writer._psi = loaded.landmarks[-1].psi if loaded.landmarks else None
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
        used up, ``lost`` counts it, ``lost_distance`` adds its d, ``lost_turn`` its heading
        change: from the previous landmark's psi, or its w x T for the first; the entries
        before it are written with the next)."""
        label = self.next_label
        self._check_open('append %s' % label)
        self._next_index += 1
        turn = (abs(wrap_angle(landmark.psi - self._psi)) if self._psi is not None
                else abs(landmark.w) * landmark.T)
        self._psi = landmark.psi
        lines, gap_key, offset = [], None, self._offset
        if self.pending_gap is not None:
            gap_key = 'gap_%d' % (self._gaps + 1)
            lines.append(flow_line(gap_key, {'before': label, 'reason': self.pending_gap}))
        if sample is not None and (sample.recording, sample.seq - (self._next_index - 1)) != offset:
            offset = (sample.recording, sample.seq - (self._next_index - 1))
            lines.append(flow_line('samples_%d' % (self._samples_entries + 1), {
                'from': label, 'recording': float(sample.recording), 'sample': int(sample.seq)}))
        lines.append(format_entry(label, landmark))
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
        """Write a gap entry before the next landmark (its ``d`` will not start at
        the previous landmark); return the entry's key. StorageError on failure."""
        self._check_open('note a gap')
        key = 'gap_%d' % (self._gaps + 1)
        try:
            self._write_line(flow_line(key, {'before': self.next_label, 'reason': str(reason)}))
        except OSError as error:
            raise StorageError(self.path, error, 'write %s to' % key, lost=self.lost)
        self._gaps += 1
        return key

    def finish(self):
        """Mark the recording finished (a later :meth:`resume` will not append)
        and close. StorageError if the mark cannot be written (still closed)."""
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

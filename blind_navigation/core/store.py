"""The landmark store's reader: a landmark file read back and validated.

:func:`load_landmarks` reads a file (format: core/landmark_format.py) with its
gaps, lost landmarks and sample marks into a :class:`LoadedPath`; a bad entry
raises LandmarkFileError naming the file and the entry. Writing:
core/landmark_writer.py; mission files: core/mission_files.py. Why lines,
gaps, sample marks and mission files: docs/recording.md, "File".
"""
import yaml

from .files import NotRegularFileError, read_regular_file
from .landmark import Limits, landmark_from_values
from .landmark_format import (FINISHED_KEY, GAP_RE, LABEL_PREFIX, LABEL_RE, MAX_FILE_BYTES,
                              METADATA_KEY, SAMPLES_RE, Gap, LandmarkFileError, SampleMark,
                              drop_torn_tail, label_for, parse)


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
    intact = drop_torn_tail(path, text, warnings)
    try:
        document = parse(intact)
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

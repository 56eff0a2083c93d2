"""The landmark file's format (one flow-map line per entry: header, ``landmark_NNNNNN``,
``gap_<n>``, ``samples_<n>``, ``finished``; INTERFACE.md) and its validating reader
:func:`load_landmarks`. Writing: core/mission_files.py; docs/recording.md, "File"."""
import re
from collections import namedtuple
from types import SimpleNamespace

import yaml

from .files import FileContentError, NotRegularFileError, read_regular_file
from .landmark import Limits, landmark_from_values

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
OWN_LINES = (LABEL_PREFIX, 'gap_', 'samples_', FINISHED_KEY + ':')

Gap = namedtuple('Gap', 'before reason')
Gap.__doc__ = ('A break in the d chain before the landmark labelled ``before`` (its d does not '
               'start at the previous landmark); ``reason`` says why.')
SampleMark = namedtuple('SampleMark', 'recording seq')
SampleMark.__doc__ = ('A sample of the sampling publisher: its ``recording`` (the time the recording '
                      'started, s) and its number ``seq`` in it (1, 2, ...).')


class LandmarkFileError(FileContentError):
    """A landmark file that cannot be used; the message names the file and entry."""

    def __init__(self, path, reason, entry=None):
        super(LandmarkFileError, self).__init__(path, entry, reason)


def label_for(index):
    """The unique, ordered key of the ``index``-th landmark (1-based)."""
    return '%s%06d' % (LABEL_PREFIX, index)


def format_number(value):
    """Six significant digits that YAML 1.1 reads as a float ('1e-05' needs a '.')."""
    mantissa, e, exponent = ('%.6g' % value).partition('e')
    if '.' not in mantissa:
        mantissa += '.0'
    return mantissa + e + exponent


def format_entry(label, landmark):
    """One line of the store for ``landmark`` under ``label``."""
    return '%s: {data: [%s]}\n' % (label, ', '.join(format_number(v) for v in landmark))


def flow_line(key, value):
    """``key: {...}`` on one line (YAML flow style)."""
    return '%s: %s' % (key, yaml.safe_dump(value, default_flow_style=True, width=1 << 30))


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


def parse(text):
    return yaml.load(text, Loader=_UniqueKeyLoader)


def drop_torn_tail(path, text, warnings):
    """``text`` without a torn last entry (a killed writer's partial line)."""
    if text and not text.endswith('\n'):
        cut = text.rfind('\n') + 1
        warnings.append('%s: dropped a torn last entry (no end of line): %r' % (path, text[cut:][:80]))
        return text[:cut]
    lines = text.splitlines(True)
    if lines and lines[-1].startswith(OWN_LINES):
        try:
            parse(lines[-1])
        except yaml.YAMLError:
            warnings.append('%s: dropped an unparsable last entry: %r' % (path, lines[-1][:80]))
            return ''.join(lines[:-1])
    return text


class LoadedPath(SimpleNamespace):
    """What :func:`load_landmarks` read: ``landmarks``, ``labels``, ``metadata``, ``warnings``, ``gaps``,
    ``finished``, ``dropped``, ``size``, ``intact_bytes``, ``last_index`` and its ``sample``."""

    @property
    def total_distance(self):
        return sum(landmark.d for landmark in self.landmarks)

    @property
    def missing(self):
        """Landmarks lost to write failures (holes in the label numbering)."""
        return self.last_index - len(self.landmarks) if self.landmarks else 0

    def lost_after_end(self, reported_lost):
        """Of the recorder's ``reported_lost`` landmarks, those after the file's last one."""
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
    """The SampleMark of label ``last_index`` by the latest ``samples_`` entry at or before it."""
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
    document = {} if document is None else document
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
    return LoadedPath(path=path, landmarks=landmarks, labels=labels, warnings=warnings, gaps=gaps,
                      metadata=metadata.get(METADATA_KEY, {}) or {}, finished=FINISHED_KEY in metadata,
                      dropped=1 if intact != text else 0, size=len(data),
                      intact_bytes=len(intact.encode('utf-8')), last_index=previous_index,
                      gap_entries=gap_entries, samples_entries=len(marks),
                      sample=_last_sample(marks, previous_index))

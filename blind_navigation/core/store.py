"""The YAML landmark store: one line per path landmark, written incrementally.

Format (see INTERFACE.md), readable by PyYAML and by yaml-cpp::

    # comment lines
    blind_navigation: {format: 1, fields: [v, w, d, T, psi], started: '...'}
    landmark_000001: {data: [0.0861, 0.0012, 0.1718, 2.0, 0.0131]}
    landmark_000002: {data: [0.0859, 0.0964, 0.0862, 1.0, 0.061]}

Writing: each landmark is one line, written, flushed and (optionally) fsynced
before ``append`` returns, so a killed writer loses at most the landmark in
flight. A torn last line (no newline, or unparsable) is dropped on load and
reported. A mission is never written over an earlier mission's file:
:func:`start_mission_file` creates a new time-stamped file and points the
configured ``landmark_file`` name at it with a symlink.
"""
import datetime
import os
import re

import yaml

from .landmark import FIELDS, Limits, landmark_from_values

LABEL_PREFIX = 'landmark_'
LABEL_RE = re.compile(r'^landmark_(\d+)$')
METADATA_KEY = 'blind_navigation'
FORMAT_VERSION = 1


class LandmarkFileError(Exception):
    """A landmark file that cannot be used; the message names the file and entry."""

    def __init__(self, path, reason, entry=None):
        self.path = path
        self.entry = entry
        self.reason = reason
        where = '%s: %s' % (path, entry) if entry else str(path)
        super(LandmarkFileError, self).__init__('%s: %s' % (where, reason))


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


class LandmarkWriter(object):
    """Appends landmarks to a new file, one durable line each.

    The file must not exist yet (an earlier mission is never overwritten).
    """

    def __init__(self, path, metadata=None, fsync=True):
        self.path = path
        self.fsync = fsync
        self.count = 0
        self.total_distance = 0.0
        parent = os.path.dirname(os.path.abspath(path))
        os.makedirs(parent, exist_ok=True)
        self._file = open(path, 'x')  # 'x': refuse to overwrite anything
        header = {'format': FORMAT_VERSION, 'fields': list(FIELDS)}
        header.update(metadata or {})
        self._file.write('# blind_navigation path landmarks [v, w, d, T, psi] '
                         '(m/s, rad/s, m, s, rad; d from the previous landmark)\n')
        self._file.write('%s: %s' % (METADATA_KEY, yaml.safe_dump(
            header, default_flow_style=True, width=1000)))
        self._sync()

    @property
    def bytes(self):
        """Size of the file so far, bytes."""
        return self._file.tell()

    def append(self, landmark):
        """Write ``landmark`` durably; return its label."""
        self.count += 1
        label = label_for(self.count)
        self._file.write(format_entry(label, landmark))
        self._sync()
        self.total_distance += landmark.d
        return label

    def _sync(self):
        self._file.flush()
        if self.fsync:
            os.fsync(self._file.fileno())

    def close(self):
        if not self._file.closed:
            self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class LoadedPath(object):
    """What :func:`load_landmarks` read: landmarks in recording order, their labels,
    the metadata map (may be empty) and warnings (e.g. a dropped torn entry)."""

    def __init__(self, path, landmarks, labels, metadata, warnings):
        self.path = path
        self.landmarks = landmarks
        self.labels = labels
        self.metadata = metadata
        self.warnings = warnings

    @property
    def total_distance(self):
        return sum(landmark.d for landmark in self.landmarks)

    @property
    def total_duration(self):
        return sum(landmark.T for landmark in self.landmarks)


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
    """Return ``text`` without a torn last entry (a killed writer's partial line)."""
    if not text or text.endswith('\n'):
        body, last = text, None
    else:
        cut = text.rfind('\n') + 1
        body, last = text[:cut], text[cut:]
    if last is not None:
        warnings.append('%s: dropped a torn last entry (no end of line): %r' % (path, last[:80]))
        return body
    lines = body.splitlines(True)
    if lines and lines[-1].startswith(LABEL_PREFIX):
        try:
            _parse(lines[-1])
        except yaml.YAMLError:
            warnings.append('%s: dropped an unparsable last entry: %r' % (path, lines[-1][:80]))
            return ''.join(lines[:-1])
    return body


def load_landmarks(path, limits=Limits(), allow_empty=False):
    """Read and validate a landmark file; raise LandmarkFileError on the first bad entry."""
    try:
        with open(path) as stream:
            text = stream.read()
    except (IOError, OSError) as error:
        raise LandmarkFileError(path, 'cannot read: %s' % (error.strerror or error))
    except UnicodeDecodeError as error:
        raise LandmarkFileError(path, 'not a text file: %s' % error)
    warnings = []
    text = _drop_torn_tail(path, text, warnings)
    try:
        document = _parse(text)
    except yaml.YAMLError as error:
        raise LandmarkFileError(path, 'not valid YAML: %s' % str(error).replace('\n', ' '))
    if document is None:
        document = {}
    if not isinstance(document, dict):
        raise LandmarkFileError(path, 'top level must be a map of landmark entries, got %s'
                                % type(document).__name__)
    landmarks, labels, metadata = [], [], {}
    previous_index = 0
    for key, value in document.items():
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
    return LoadedPath(path, landmarks, labels, metadata.get(METADATA_KEY, {}) or {}, warnings)


def mission_file_name(landmark_file, when=None):
    """The time-stamped file a mission started at ``when`` records into."""
    when = when or datetime.datetime.now()
    stem, ext = os.path.splitext(landmark_file)
    return '%s-%s%s' % (stem, when.strftime('%Y%m%d-%H%M%S'), ext or '.yaml')


def start_mission_file(landmark_file, when=None):
    """Choose a new file for a mission and point ``landmark_file`` at it.

    Returns the new (not yet created) path. An existing regular file at
    ``landmark_file`` is kept by renaming it to a time-stamped name first; an
    existing symlink is replaced atomically. Nothing recorded is deleted.
    """
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    directory = os.path.dirname(landmark_file)
    os.makedirs(directory, exist_ok=True)
    if os.path.exists(landmark_file) and not os.path.islink(landmark_file):
        mtime = datetime.datetime.fromtimestamp(os.path.getmtime(landmark_file))
        os.rename(landmark_file, _unused(mission_file_name(landmark_file, mtime)))
    target = _unused(mission_file_name(landmark_file, when))
    link = landmark_file + '.tmp-link'
    if os.path.lexists(link):
        os.remove(link)
    os.symlink(os.path.basename(target), link)
    os.replace(link, landmark_file)
    return target


def write_atomically(path, text):
    """Replace ``path`` by ``text`` atomically (temporary file in the same directory,
    fsync, rename): a crash leaves the old or the new content, never a mix."""
    temporary = path + '.tmp'
    with open(temporary, 'w') as stream:
        stream.write(text)
        stream.flush()
        os.fsync(stream.fileno())
    os.replace(temporary, path)


def _unused(path):
    """``path``, or ``path`` with a -N suffix if that name is already taken."""
    stem, ext = os.path.splitext(path)
    candidate, n = path, 1
    while os.path.lexists(candidate):
        candidate = '%s-%d%s' % (stem, n, ext)
        n += 1
    return candidate


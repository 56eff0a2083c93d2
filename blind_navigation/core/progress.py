"""The persisted progress of a return: :class:`ReturnProgress` (``begin``, ``start``,
``goal_done``, ``finish``, each a new validated record) and its file."""
import hashlib
import math
import os
import re
from collections import namedtuple

import yaml

from . import mission_state as state
from .files import FileContentError, NotRegularFileError, read_regular_file, write_atomically
from .geometry import OdomState
from .heading_correction import GyroCorrection
from .route import Route

#: Defaults of the resume rule.
PROGRESS_DEFAULTS = {
    'resume_timeout': 600.0,   # s (wall) after which an unfinished return is not resumed but aborted
    'resume_max_offset': 0.5,  # m between the robot and where the return stopped, to resume
}

#: The layout of the progress file; a file of another version is not resumed.
FORMAT_VERSION = 2
ROUTE_RECORD = ('route', 'heading')
FIELDS = ('landmark_file', 'digest', 'landmarks', 'anchor', 'frame_id', 'completed', 'position',
          'status', 'updated', 'route', 'reason', 'mission', 'started', 'travelled')
STATUSES = (state.ROTATING, state.RETURNING, state.HOME, state.ABORTED, state.RECOVERED)
UNFINISHED = (state.ROTATING, state.RETURNING)
MAX_PROGRESS_BYTES = 16 << 20     # a route of ~100000 waypoints
MAX_ROUTE_DEPTH = 16


_HEX_DIGEST = re.compile(r'^[0-9a-f]{64}$')


class ProgressError(FileContentError):
    """A return progress that cannot be trusted (``part``: the field, or None)."""


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _is_count(value):
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _is_point(value):
    return isinstance(value, list) and len(value) == 2 and all(_is_number(c) for c in value)


def as_point(value):
    """``value`` as [x, y] floats (None stays None); ValueError if not a finite point."""
    if value is None:
        return None
    point = list(value) if isinstance(value, (list, tuple)) else value
    if not _is_point(point):
        raise ValueError('a point must be [x, y] (finite numbers), got %r' % (value,))
    return [float(c) for c in point]


def _plain(value, depth=0):
    """``value`` as plain data (tuples -> lists); ValueError if it is not plain data."""
    if depth > MAX_ROUTE_DEPTH:
        raise ValueError('nested deeper than %d levels' % MAX_ROUTE_DEPTH)
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, float)):
        if not math.isfinite(value):
            raise ValueError('not a finite number: %r' % (value,))
        return value
    if isinstance(value, (list, tuple)):
        return [_plain(item, depth + 1) for item in value]
    if isinstance(value, dict):
        if not all(isinstance(key, str) for key in value):
            raise ValueError('map keys must be strings: %r' % (sorted(map(repr, value)),))
        return {key: _plain(item, depth + 1) for key, item in value.items()}
    raise ValueError('not plain data: %s' % type(value).__name__)


def _route(value):
    """A route record ({'route': Route.to_lists(), 'heading': plain or None}) or None, as
    stored; ValueError naming what is wrong."""
    if value is None:
        return None
    if not isinstance(value, dict) or set(value) != set(ROUTE_RECORD):
        raise ValueError('route must be null or a map of exactly %s, got %r'
                         % (', '.join(ROUTE_RECORD), value if not isinstance(value, dict)
                            else sorted(value)))
    Route.from_lists(value['route'])
    heading = value['heading']
    if heading is not None and not isinstance(heading, dict):
        raise ValueError('route heading must be a map or null, got %s' % type(heading).__name__)
    return {'route': _plain(value['route']), 'heading': _plain(heading)}


def heading_record(correction, reference, frame=None):
    """The plain form of a GyroCorrection (infinite std as None), the raw OdomState where its
    frame starts and the feed's frame snapshot or None."""
    return {'correction': [None if isinstance(v, float) and not math.isfinite(v) else v
                           for v in correction],
            'reference': [reference.x, reference.y, reference.yaw, reference.stamp],
            'frame': frame}


def plain_correction(plain):
    """(GyroCorrection, OdomState, snapshot) of a :func:`heading_record`; ValueError if unreadable."""
    try:
        correction = GyroCorrection(*(float('inf') if v is None else v for v in plain['correction']))
        reference = OdomState(*(float(v) for v in plain['reference'][:3]), 0.0, 0.0,
                              float(plain['reference'][3]))
        return correction, reference, plain.get('frame')
    except (KeyError, TypeError, ValueError, IndexError):
        raise ValueError('the kept heading correction is not readable: %r' % (plain,))


def _field_problem(progress):
    """(field, reason) of the first thing wrong in ``progress``, or None."""
    p = progress
    if p.status not in STATUSES:
        return 'status', 'must be one of %s, got %r' % (', '.join(STATUSES), p.status)
    returned = p.status in (state.RETURNING, state.HOME)
    if not isinstance(p.landmark_file, str):
        return 'landmark_file', 'must be a path, got %r' % (p.landmark_file,)
    if (p.landmark_file or p.status != state.ABORTED) and not os.path.isabs(p.landmark_file):
        return 'landmark_file', 'must be an absolute path, got %r' % (p.landmark_file,)
    if not isinstance(p.digest, str) or not (_HEX_DIGEST.match(p.digest) or (p.digest == '' and not returned)):
        return 'digest', 'must be the landmark file\'s sha256 (64 hex digits)%s, got %r' % (
            '' if returned else ' or empty', p.digest)
    if not _is_count(p.landmarks) or (returned and p.landmarks < 1):
        return 'landmarks', 'must be a count %s, got %r' % ('>= 1' if returned else '>= 0', p.landmarks)
    if not _is_count(p.completed) or p.completed > p.landmarks:
        return 'completed', 'must be a count from 0 to landmarks (%r), got %r' % (p.landmarks, p.completed)
    if p.status == state.HOME and p.completed != p.landmarks:
        return 'completed', 'home needs every landmark completed (%r), got %r' % (p.landmarks, p.completed)
    for name in ('anchor', 'position'):
        value = getattr(p, name)
        if value is not None and not _is_point(value):
            return name, 'must be [x, y] (finite numbers) or null, got %r' % (value,)
    if returned and p.anchor is None:
        return 'anchor', 'a return needs its anchor, got null'
    if not isinstance(p.frame_id, str):
        return 'frame_id', 'must be a string, got %r' % (p.frame_id,)
    if not _is_number(p.updated) or p.updated < 0:
        return 'updated', 'must be a wall time (s, finite, >= 0), got %r' % (p.updated,)
    if p.started is not None and not (_is_number(p.started) and 0 <= p.started <= p.updated):
        return 'started', 'must be a wall time (s) not after updated (%r) or null, got %r' % (
            p.updated, p.started)
    if not _is_number(p.travelled) or p.travelled < 0:
        return 'travelled', 'must be a distance (m, finite, >= 0), got %r' % (p.travelled,)
    if not isinstance(p.reason, str):
        return 'reason', 'must be a string, got %r' % (p.reason,)
    if p.mission is not None and not (isinstance(p.mission, str) and p.mission):
        return 'mission', 'must be a non-empty string or null, got %r' % (p.mission,)
    try:
        if _route(p.route) != p.route:
            return 'route', 'must be plain data (lists, not tuples; floats)'
    except ValueError as error:
        return 'route', str(error)
    return None


class ReturnProgress(namedtuple('ReturnProgress', FIELDS, defaults=(None, '', None, None, 0.0))):
    """State of one return (docs/safety.md, "Faults"): positions are odometry [x, y], times
    wall s; ``digest`` '' until the return starts; ``travelled``: m for core/plausibility.RouteBudget."""

    __slots__ = ()

    @classmethod
    def begin(cls, landmark_file, anchor, frame_id, now, mission=None):
        """Vision was lost at ``anchor`` [x, y]: a return over ``landmark_file`` begins with
        the pi turn."""
        anchor = as_point(anchor)
        return cls(landmark_file=os.path.realpath(os.path.expanduser(landmark_file)), digest='',
                   landmarks=0, anchor=anchor, frame_id=str(frame_id or ''), completed=0,
                   position=anchor, status=state.ROTATING, updated=float(now), reason='',
                   mission=mission, started=float(now)).checked()

    def start(self, digest, landmarks, now, route=None):
        """The robot starts back over ``landmarks`` landmarks of a file with sha256 ``digest``."""
        if self.status != state.ROTATING:
            raise ValueError('a return starts after the pi turn (status rotating), not in %s'
                             % self.status)
        return self._replace(digest=digest, landmarks=landmarks, status=state.RETURNING,
                             updated=float(now), route=_route(route)).checked()

    def goal_done(self, completed, now, position=None, travelled=None):
        """``completed`` goals are done (never fewer than before)."""
        if self.status != state.RETURNING:
            raise ValueError('goals are done while returning, not in %s' % self.status)
        if not (_is_count(completed) and self.completed <= completed <= self.landmarks):
            raise ValueError('completed must go from %d up to %d, got %r'
                             % (self.completed, self.landmarks, completed))
        changes = dict(completed=completed, updated=float(now))
        if position is not None:
            changes['position'] = as_point(position)
        if travelled is not None:
            changes['travelled'] = float(travelled)
        return self._replace(**changes).checked()

    def finish(self, status, reason, now, position=None):
        """The return ended ``home``, ``aborted`` or ``recovered``, for ``reason``."""
        if status not in (state.HOME, state.ABORTED, state.RECOVERED):
            raise ValueError('a return finishes home, aborted or recovered, not %r' % (status,))
        if not self.unfinished and status != self.status:
            raise ValueError('the return already ended %s' % self.status)
        changes = dict(status=status, reason=str(reason), updated=float(now))
        if position is not None:
            changes['position'] = as_point(position)
        return self._replace(**changes).checked()

    unfinished = property(lambda self: self.status in UNFINISHED)

    def checked(self, path='<return progress>'):
        problem = _field_problem(self)
        if problem:
            raise ProgressError(path, *problem)
        return self


def progress_path(landmark_file):
    """``<stem>.progress.yaml`` next to ``landmark_file`` (the configured name)."""
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    stem, _ = os.path.splitext(os.path.basename(landmark_file))
    return os.path.join(os.path.dirname(landmark_file), stem + '.progress.yaml')


def file_digest(path):
    """sha256 of a regular file's bytes (hex); OSError if it cannot be read."""
    return hashlib.sha256(read_regular_file(path, 1 << 30)).hexdigest()


def save_progress(path, progress):
    """Validate ``progress`` and write it to ``path`` atomically (StorageError on failure)."""
    progress.checked(path)
    document = dict([('format', FORMAT_VERSION)] + list(progress._asdict().items()))
    text = ('# blind_navigation return progress (back_travel_client); '
            'the landmark file itself is never modified\n'
            + yaml.safe_dump(document, default_flow_style=None, sort_keys=False, width=1 << 16))
    write_atomically(path, text)


def load_progress(path):
    """The :class:`ReturnProgress` at ``path`` (None: none); ProgressError if untrusted."""
    try:
        data = read_regular_file(path, MAX_PROGRESS_BYTES, follow_symlinks=False)
    except FileNotFoundError:
        return None
    except NotRegularFileError as error:
        raise ProgressError(path, None, 'is %s, not a regular file' % error.what)
    except OSError as error:
        raise ProgressError(path, None, 'cannot read: %s' % (error.strerror or error))
    try:
        document = yaml.safe_load(data.decode('utf-8'))
    except (UnicodeDecodeError, yaml.YAMLError) as error:
        raise ProgressError(path, None, 'not a YAML text: %s' % str(error).replace('\n', ' '))
    if not isinstance(document, dict):
        raise ProgressError(path, None, 'must be a map of %s, got %s'
                            % (', '.join(FIELDS), type(document).__name__))
    version = document.pop('format', None)
    if version != FORMAT_VERSION:
        raise ProgressError(path, 'format', 'must be %d, got %r%s' % (
            FORMAT_VERSION, version, ' (written by an older version of the layer: its return '
            'is not resumed)' if isinstance(version, int) and version < FORMAT_VERSION else ''))
    missing = [name for name in FIELDS if name not in document]
    if missing:
        raise ProgressError(path, missing[0], 'missing')
    unknown = sorted(str(key) for key in document if key not in FIELDS)
    if unknown:
        raise ProgressError(path, unknown[0], 'unknown field')
    return ReturnProgress(**document).checked(path)

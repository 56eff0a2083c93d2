"""Safety rules of the return, without ROS: velocity limits per goal, Kobuki
safety events, time allowances, and the persisted progress of a return.

- :func:`goal_limits` / :meth:`VelocityLimits.clamp`: a goal is never driven
  faster than the configured limits nor faster than the robot went over that
  landmark (linear: the larger of the recorded end speed ``|v|`` and the mean
  speed ``d / T``; angular: the recorded ``|w|`` plus a correction allowance
  for the closed-loop steering). Clamping scales ``v`` and ``w`` together, so
  the commanded curvature (the path's shape) is kept.
- :class:`SafetyEvents`: Kobuki bumper, cliff and wheel-drop events
  (kobuki_msgs/BumperEvent, CliffEvent, WheelDropEvent fields) -> which
  conditions are active and why the robot must stop.
- :func:`expected_duration` / :func:`return_allowance`: time allowances.
- :class:`ReturnProgress` + :func:`save_progress` / :func:`load_progress`: the
  progress of a return (the landmark file's real path and digest, the
  anchor, the landmarks completed) written atomically next to the landmark
  file, and :func:`resume_check`, which decides whether a restarted layer may
  resume it. The recorded landmark file itself is only ever read.
"""
import hashlib
import math
import os
from collections import namedtuple

import yaml

from .landmark import landmark_from_values
from .store import write_atomically

#: Defaults of the safety params (the nodes expose them as ~private params).
SAFETY_DEFAULTS = {
    'correction_w': 0.3,       # rad/s a goal may turn beyond its recorded |w| (closed-loop steering)
    'slowest_v': 0.03,         # m/s assumed for landmarks recorded slower, when timing a goal
    'resume_timeout': 600.0,   # s (wall) after which an unfinished return is not resumed
    'resume_max_offset': 0.5,  # m between the robot and where the return stopped, to resume
}


class VelocityLimits(namedtuple('VelocityLimits', 'max_v max_w')):
    """Largest |v| (m/s) and |w| (rad/s) to command."""

    __slots__ = ()

    def clamp(self, v, w):
        """``(v, w)`` scaled down by one common factor so that both are within the
        limits (keeps the curvature w / v); non-finite input gives (0, 0)."""
        if not (math.isfinite(v) and math.isfinite(w)):
            return 0.0, 0.0
        factor = 1.0
        if abs(v) > self.max_v:
            factor = min(factor, self.max_v / abs(v))
        if abs(w) > self.max_w:
            factor = min(factor, self.max_w / abs(w))
        return v * factor, w * factor


def recorded_speed(landmark):
    """How fast the robot went over ``landmark``: the larger of its end speed |v|
    and its mean speed d / T, m/s."""
    return max(abs(landmark.v), landmark.d / landmark.T)


def goal_limits(landmark, max_v, max_w, correction_w=SAFETY_DEFAULTS['correction_w']):
    """Limits for driving ``landmark`` back: the configured ``max_v``/``max_w``,
    and never faster than recorded (:func:`recorded_speed`; |w| + ``correction_w``)."""
    if max_v < 0 or max_w < 0 or correction_w < 0:
        raise ValueError('limits must not be negative: max_v %r, max_w %r, correction_w %r'
                         % (max_v, max_w, correction_w))
    return VelocityLimits(min(max_v, recorded_speed(landmark)),
                          min(max_w, abs(landmark.w) + correction_w))


def expected_duration(landmark, slowest_v=SAFETY_DEFAULTS['slowest_v']):
    """Time a goal should take: its period T, or d at its recorded speed (at least
    ``slowest_v``) if that is longer, s."""
    return max(landmark.T, landmark.d / max(abs(landmark.v), slowest_v))


def return_allowance(landmarks, factor, margin, slowest_v=SAFETY_DEFAULTS['slowest_v']):
    """Time allowed for a whole return over ``landmarks``: ``factor`` x the sum of
    the expected durations + ``margin``, s."""
    return factor * sum(expected_duration(lm, slowest_v) for lm in landmarks) + margin


# --- Kobuki safety events ----------------------------------------------------

#: kind -> (sensor names by index, the state value that means "stop", its word)
EVENT_LAYOUT = {
    'bumper': (('left', 'center', 'right'), 1, 'pressed'),       # BumperEvent.PRESSED
    'cliff': (('left', 'center', 'right'), 1, 'cliff'),          # CliffEvent.CLIFF
    'wheel_drop': (('left', 'right'), 1, 'dropped'),             # WheelDropEvent.DROPPED
}


class SafetyEvents(object):
    """Which Kobuki safety sensors are active (bumper pressed, cliff seen, wheel
    dropped). :meth:`update` takes one event's fields and returns the reason to
    stop when a sensor becomes active, else None."""

    def __init__(self):
        self._active = {}       # (kind, index) -> reason

    def update(self, kind, index, sensor_state):
        if kind not in EVENT_LAYOUT:
            raise ValueError('unknown safety event kind %r (expected one of %s)'
                             % (kind, ', '.join(sorted(EVENT_LAYOUT))))
        names, stop_value, word = EVENT_LAYOUT[kind]
        name = names[index] if 0 <= index < len(names) else 'sensor %d' % index
        key = (kind, index)
        if sensor_state != stop_value:
            self._active.pop(key, None)
            return None
        reason = '%s %s %s' % (kind.replace('_', ' '), name, word)
        self._active[key] = reason
        return reason

    @property
    def active(self):
        """Reasons of the sensors active now (empty: safe to drive)."""
        return sorted(self._active.values())


# --- return progress ---------------------------------------------------------

PROGRESS_FIELDS = ('landmark_file', 'digest', 'landmarks', 'anchor', 'frame_id', 'completed',
                   'position', 'status', 'updated')
#: Statuses of a return in progress; anything else is finished.
UNFINISHED = ('rotating', 'returning')


class ProgressError(Exception):
    """A progress file that cannot be used; the message names the file."""


class ReturnProgress(namedtuple('ReturnProgress', PROGRESS_FIELDS)):
    """State of one return: ``landmark_file`` (real path of the recorded file),
    ``digest`` (its sha256, '' until loaded), ``landmarks`` (its count),
    ``anchor`` ([x, y] odometry where recording stopped, or None),
    ``frame_id`` (odometry frame), ``completed`` (goals done, return order),
    ``position`` ([x, y] odometry at the last update, or None), ``status``
    (rotating, returning, home, aborted), ``updated`` (wall time, s)."""

    __slots__ = ()

    @property
    def unfinished(self):
        return self.status in UNFINISHED


def progress_path(landmark_file):
    """Where the progress of a return over ``landmark_file`` (the configured name,
    usually the recorder's symlink) is kept: next to it, ``<stem>.progress.yaml``."""
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    stem, _ = os.path.splitext(os.path.basename(landmark_file))
    return os.path.join(os.path.dirname(landmark_file), stem + '.progress.yaml')


def file_digest(path):
    """sha256 of a file's bytes (hex)."""
    digest = hashlib.sha256()
    with open(path, 'rb') as stream:
        for block in iter(lambda: stream.read(1 << 16), b''):
            digest.update(block)
    return digest.hexdigest()


def save_progress(path, progress):
    """Write ``progress`` to ``path`` atomically (temporary file in the same
    directory, fsync, rename): a crash leaves the old or the new progress."""
    text = ('# blind_navigation return progress (back_travel_client); '
            'the landmark file itself is never modified\n'
            + yaml.safe_dump(dict(progress._asdict()), default_flow_style=False, sort_keys=False))
    write_atomically(path, text)


def load_progress(path):
    """The progress stored at ``path``, or None if there is none; ProgressError
    (naming the file) if it is unreadable or malformed."""
    try:
        with open(path) as stream:
            document = yaml.safe_load(stream)
    except FileNotFoundError:
        return None
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as error:
        raise ProgressError('%s: unreadable progress file: %s' % (path, str(error).replace('\n', ' ')))
    if not isinstance(document, dict) or set(document) != set(PROGRESS_FIELDS):
        raise ProgressError('%s: progress file must be a map with keys %s'
                            % (path, ', '.join(PROGRESS_FIELDS)))
    progress = ReturnProgress(**document)
    for name in ('anchor', 'position'):
        value = getattr(progress, name)
        if value is not None and not _is_point(value):
            raise ProgressError('%s: %s must be [x, y] (finite numbers) or null, got %r'
                                % (path, name, value))
    if not isinstance(progress.completed, int) or isinstance(progress.completed, bool) \
            or not 0 <= progress.completed:
        raise ProgressError('%s: completed must be a count >= 0, got %r' % (path, progress.completed))
    if not isinstance(progress.landmark_file, str) or not isinstance(progress.status, str):
        raise ProgressError('%s: landmark_file and status must be strings' % path)
    return progress


def _is_point(value):
    return (isinstance(value, list) and len(value) == 2
            and all(isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c)
                    for c in value))


def resume_check(progress, now, digest, resume_timeout):
    """May a restarted layer resume ``progress``? Returns ``('resume', why)``,
    ``('ignore', why)`` (nothing to resume: finished, or too old to trust) or
    ``('abort', why)`` (a return was under way but cannot safely continue).
    Where the robot is, is checked separately (:func:`position_check`) once
    odometry arrives.

    ``now``: wall time, s; ``digest``: sha256 of ``progress.landmark_file`` now
    (None if it cannot be read).
    """
    if not progress.unfinished:
        return 'ignore', 'the last return ended %s' % progress.status
    age = now - float(progress.updated)
    if not 0 <= age <= resume_timeout:
        return 'ignore', ('an unfinished return of %s was last updated %.0f s ago (resume_timeout '
                          '%.0f s); not resuming it' % (progress.landmark_file, age, resume_timeout))
    if progress.status == 'rotating':
        return 'abort', 'restarted during the pi turn: the heading is unknown, not travelling back'
    if digest is None:
        return 'abort', 'landmark file %s of the unfinished return is gone' % progress.landmark_file
    if digest != progress.digest:
        return 'abort', 'landmark file %s changed since the return started' % progress.landmark_file
    if progress.anchor is None or progress.position is None:
        return 'abort', 'the unfinished return has no anchor/position to resume from'
    return 'resume', 'resuming the return of %s after %d of %d landmarks' % (
        progress.landmark_file, progress.completed, progress.landmarks)


def position_check(progress, position, resume_max_offset):
    """None if the robot (odometry ``position`` [x, y], None if unknown) is within
    ``resume_max_offset`` m of where ``progress`` stopped, else why not."""
    if position is None:
        return 'no odometry to check where the robot is'
    offset = math.hypot(position[0] - progress.position[0], position[1] - progress.position[1])
    if offset > resume_max_offset:
        return ('the robot is %.2f m from where the return stopped (resume_max_offset %.2f m): '
                'odometry reset or robot moved' % (offset, resume_max_offset))
    return None


def landmarks_from_flat(values):
    """Landmarks from a flat list of 5-value groups [v, w, d, T, psi, ...] (as
    sent in a SetReturnRoute request); ValueError naming the bad one."""
    if len(values) % 5:
        raise ValueError('completed landmarks: %d numbers is not a multiple of 5' % len(values))
    landmarks = []
    for index in range(0, len(values), 5):
        try:
            landmarks.append(landmark_from_values(list(values[index:index + 5])))
        except ValueError as error:
            raise ValueError('completed landmark %d: %s' % (index // 5 + 1, error))
    return landmarks

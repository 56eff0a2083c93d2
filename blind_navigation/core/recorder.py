"""Path recording (paper 3.3.1): :class:`PathRecorder` turns the odometry at each sampling
tick into the path landmark; also a recording's low-space watch (:class:`SpaceWatch`)."""
import bisect
import itertools
import os
from collections import deque

from .geometry import distance, wrap_angle
from .landmark import Limits, landmark_from_values

#: Minutes of recording the free space must hold, else a warning (docs/safety.md, "Decide before the turn").
LOW_SPACE_MINUTES = 10.0
#: Bytes per minute assumed until a recording measured its own: an 80-byte line a second (its fastest).
ASSUMED_BYTES_PER_MINUTE = 80.0 * 60
#: s of recording after which its own rate replaces the assumed one.
RATE_WINDOW = 60.0


def free_bytes(directory):
    """Bytes an unprivileged writer may still use on ``directory``'s file system (None: unknown)."""
    try:
        info = os.statvfs(directory)
    except OSError:
        return None
    return info.f_bavail * info.f_frsize


class SpaceWatch(object):
    """The low-space warning of one recording into ``directory`` (``free``: :func:`free_bytes`)
    at its rate: bytes per minute measured after RATE_WINDOW s, ASSUMED_BYTES_PER_MINUTE before."""

    def __init__(self, directory, free=free_bytes):
        self.directory = directory
        self.free = free
        self.warning = ''
        self._start = None          # (s, bytes) of the first update with a landmark

    def update(self, now, size, landmarks):
        """(the warning for ``size`` bytes, ``landmarks`` at ``now`` s; True when it just appeared)."""
        if self._start is None and landmarks:
            self._start = (now, size)
        start, start_size = self._start or (now, size)
        written, free = size - start_size, self.free(self.directory)
        rate = written * 60.0 / (now - start) if now - start >= RATE_WINDOW and written > 0 \
            else ASSUMED_BYTES_PER_MINUTE
        warning = ''
        if free is not None and free < LOW_SPACE_MINUTES * rate:
            warning = ('LOW SPACE: %d bytes free on %s hold %.1f min of recording at %.0f bytes/min '
                       '(less than %g min): free space or end the mission'
                       % (free, self.directory, free / rate, rate, LOW_SPACE_MINUTES))
        appeared = bool(warning) and not self.warning
        self.warning = warning
        return warning, appeared


class OdometryHistory(object):
    """The last ``span`` s of odometry, read at a tick's stamp however late its message comes."""

    def __init__(self, span=10.0):
        if not span > 0:
            raise ValueError('odometry history span must be > 0 s, got %r' % (span,))
        self.span = float(span)
        self._states = deque()

    def append(self, state):
        """Add an OdomState; an older stamp than the last restarts the history (sim time reset)."""
        if self._states and state.stamp < self._states[-1].stamp:
            self._states.clear()
        self._states.append(state)
        while self._states[-1].stamp - self._states[0].stamp > self.span:
            self._states.popleft()

    def clear(self):
        """Forget every state (the odometry after a discontinuity is another frame)."""
        self._states.clear()

    latest = property(lambda self: self._states[-1] if self._states else None)

    def at(self, stamp):
        """The latest state stamped at or before ``stamp`` (all newer: the oldest; empty: None)."""
        if not self._states:
            return None
        return self._states[max(self._index_after(stamp) - 1, 0)]

    def after(self, stamp):
        """The states stamped after ``stamp``, oldest first."""
        if not self._states or self._states[-1].stamp <= stamp:
            return []
        return list(itertools.islice(self._states, self._index_after(stamp), None))

    def _index_after(self, stamp):
        """Index of the first state stamped after ``stamp``."""
        return bisect.bisect_right([state.stamp for state in self._states], stamp)


class PathRecorder(object):
    """Odometry at sampling ticks -> landmarks; ``d`` from the previous one (the first: :meth:`start`)."""

    def __init__(self, limits=Limits()):
        self.limits = limits
        self.origin = None          # (x, y) where recording started
        self._previous = None       # (x, y) of the previous landmark, or the origin
        self.count = 0
        self.total_distance = 0.0

    started = property(lambda self: self._previous is not None)

    def start(self, odom_state):
        """Record the start position (once; later calls are ignored)."""
        if self._previous is None:
            self.origin = (odom_state.x, odom_state.y)
            self._previous = self.origin

    def restart(self, odom_state):
        """A new ``d`` chain from ``odom_state`` (after a discontinuity); count and distance go on."""
        if self.origin is None:
            self.origin = (odom_state.x, odom_state.y)
        self._previous = (odom_state.x, odom_state.y)

    def take(self, odom_state, yaw, period):
        """The landmark of a tick (``yaw`` rad, ``period`` s); ValueError naming the field (nothing taken)."""
        self.start(odom_state)
        px, py = self._previous
        step = distance(px, py, odom_state.x, odom_state.y)
        landmark = landmark_from_values(
            [odom_state.v, odom_state.w, step, period, wrap_angle(yaw)], self.limits)
        self._previous = (odom_state.x, odom_state.y)
        self.count += 1
        self.total_distance += step
        return landmark

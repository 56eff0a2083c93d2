"""Path recording: odometry at each sampling tick -> the paper's path landmark.

Section 3.3.1 of the paper: at each tick of the sampling publisher the
recorder takes ``v`` = twist.linear.x and ``w`` = twist.angular.z from the
latest odometry, ``d`` = the straight-line distance from the previous
landmark's position (for the first landmark: from where recording started,
the first odometry seen), and ``T`` and ``psi`` from the tick itself (the
period in force and the yaw the publisher read).

Also the storage of a recorded path (section 5: count, bytes, bytes
per metre), shared by the ROS nodes and the evaluation.
"""
import bisect
import itertools
from collections import deque, namedtuple

from .geometry import distance, wrap_angle
from .landmark import Limits, landmark_from_values

PathStorage = namedtuple('PathStorage', 'landmarks bytes distance bytes_per_metre')
PathStorage.__doc__ = ('Storage used by a recorded path: landmark count, file bytes, path length '
                     '(sum of d, m) and bytes per metre (0 until the robot has moved).')


def storage_usage(landmarks, size_bytes, total_distance):
    """Storage of ``landmarks`` landmarks stored in ``size_bytes`` bytes over ``total_distance`` m."""
    per_metre = size_bytes / total_distance if total_distance > 0.0 else 0.0
    return PathStorage(int(landmarks), int(size_bytes), float(total_distance), per_metre)


class OdometryHistory(object):
    """The last ``span`` seconds of odometry, to read the odometry *at a tick's
    stamp* (the latest state stamped no later than the tick) however late the
    tick's message arrives. Both recorder variants then read the same state
    for the same tick, and the start is where the robot was when the
    publisher started, whenever the saver itself started."""

    def __init__(self, span=10.0):
        if not span > 0:
            raise ValueError('odometry history span must be > 0 s, got %r' % (span,))
        self.span = float(span)
        self._states = deque()

    def append(self, state):
        """Add an OdomState; a stamp older than the last one restarts the history
        (sim time was reset)."""
        if self._states and state.stamp < self._states[-1].stamp:
            self._states.clear()
        self._states.append(state)
        while self._states[-1].stamp - self._states[0].stamp > self.span:
            self._states.popleft()

    def clear(self):
        """Forget every state (the odometry after a discontinuity is another frame)."""
        self._states.clear()

    @property
    def latest(self):
        return self._states[-1] if self._states else None

    def at(self, stamp):
        """The latest state stamped at or before ``stamp``; the oldest kept if all
        are newer; None if empty."""
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
    """Turns odometry at sampling ticks into path landmarks ``(v, w, d, T, psi)``.

    Call :meth:`start` with the first odometry seen (where recording starts);
    :meth:`take` starts implicitly from its own odometry if :meth:`start` was
    never called (the first landmark then has ``d = 0``).
    """

    def __init__(self, limits=Limits()):
        self.limits = limits
        self.origin = None          # (x, y) where recording started
        self._previous = None       # (x, y) of the previous landmark, or the origin
        self.count = 0
        self.total_distance = 0.0

    @property
    def started(self):
        return self._previous is not None

    def start(self, odom_state):
        """Record the start position (once; later calls are ignored)."""
        if self._previous is None:
            self.origin = (odom_state.x, odom_state.y)
            self._previous = self.origin

    def take(self, odom_state, yaw, period):
        """The landmark for a tick with yaw ``yaw`` (rad) and period ``period`` (s).

        Raises ValueError (naming the field) when the result is not a valid
        landmark, e.g. a non-positive period or a velocity beyond the limits;
        the recorder's position is then unchanged, so the next landmark's
        ``d`` still counts from the last landmark actually taken.
        """
        self.start(odom_state)
        px, py = self._previous
        step = distance(px, py, odom_state.x, odom_state.y)
        landmark = landmark_from_values(
            [odom_state.v, odom_state.w, step, period, wrap_angle(yaw)], self.limits)
        self._previous = (odom_state.x, odom_state.y)
        self.count += 1
        self.total_distance += step
        return landmark


def record_path(odom_at, duration, schedule, recorder=None):
    """Plain-Python run of the sampling publisher and saver over a known path.

    ``odom_at(t)`` gives the OdomState ``t`` s after recording started;
    ``schedule`` is a :class:`~.segment.SamplingSchedule`. As in the nodes,
    the start yaw is the schedule's first yaw, each tick feeds the schedule
    its yaw, the next period comes from the schedule, and at ``duration``
    (vision lost) a final landmark covers the partial cycle since the last
    tick. Returns ``[(tick time, Landmark), ...]``.
    """
    recorder = recorder or PathRecorder()
    start = odom_at(0.0)
    recorder.start(start)
    period = schedule.update(start.yaw)
    t, ticks = 0.0, []
    while t + period <= duration + 1e-9:
        t += period
        odom = odom_at(t)
        ticks.append((t, recorder.take(odom, odom.yaw, period)))
        period = schedule.update(odom.yaw)
    if duration - t > 1e-9:
        odom = odom_at(duration)
        ticks.append((duration, recorder.take(odom, odom.yaw, duration - t)))
    return ticks

"""Gyro yaw against visual-odometry yaw: :class:`GyroVisualFit` cuts them into windows and
fits ``dpsi_gyro - dpsi_vo = s dpsi_vo + b dt`` (:func:`robust_fit`). docs/back_travel.md,
"Gyro heading correction"."""
import math
from array import array
from collections import deque

from .geometry import wrap_angle

GYRO_FIT_DEFAULTS = {
    'window': 2.0,               # s, length of one yaw-increment window
    'max_gap': 0.5,              # s, a longer gap between samples breaks the window
    'min_windows': 10,           # fewer usable windows: no visual-odometry estimate
    'outlier_k': 5.0,            # windows beyond this many robust std of the residuals are dropped
}

#: How much odometry history is kept to interpolate at visual-odometry stamps, s.
HISTORY = 5.0
#: Visual-odometry samples kept while waiting for odometry to cover their stamps.
MAX_PENDING = 300
#: Windows kept (2 hours of 2 s windows); past it the oldest half is dropped.
MAX_WINDOWS = 3600


class WindowRows(object):
    """The fit's windows ``(gyro increment, VO increment, dt)``, packed; the oldest half dropped when full."""

    def __init__(self, capacity=MAX_WINDOWS):
        if not capacity >= 2:
            raise ValueError('window capacity must be >= 2, got %r' % (capacity,))
        self.capacity = int(capacity)
        self._values = array('d')

    def append(self, row):
        if len(self) >= self.capacity:
            del self._values[:3 * (len(self) // 2)]
        gyro, vo, dt = row
        self._values.extend((gyro, vo, dt))

    def __len__(self):
        return len(self._values) // 3

    def __iter__(self):
        values = self._values
        return (tuple(values[i:i + 3]) for i in range(0, len(values), 3))


class GyroVisualFit(object):
    """Gyro and VO yaw as they come, one row per window in ``rows`` (``params``: GYRO_FIT_DEFAULTS')."""

    def __init__(self, params=None):
        for name, default in GYRO_FIT_DEFAULTS.items():
            setattr(self, name, float(getattr(params, name, default)))
        if self.window <= 0 or self.max_gap <= 0 or self.min_windows < 3:
            raise ValueError('gyro fit: need window > 0, max_gap > 0, min_windows >= 3 '
                             '(window %r, max_gap %r, min_windows %r)'
                             % (self.window, self.max_gap, self.min_windows))
        self.rows = WindowRows()    # (gyro increment, VO increment, dt) per window
        self._first_stamp = None    # of the first odometry
        self._odom = deque()        # (stamp, unwrapped gyro yaw)
        self._pending = deque()     # (stamp, VO yaw or None) not yet covered by odometry
        self._last_vo = None        # (stamp, unwrapped VO yaw, wrapped VO yaw) of the last sample
        self._start = None          # (stamp, VO yaw, gyro yaw) where the current window began

    def add_odometry(self, stamp, yaw):
        """A raw odometry yaw (rad) at ``stamp`` (s)."""
        if self._odom and stamp <= self._odom[-1][0]:
            return
        if self._first_stamp is None:
            self._first_stamp = stamp
        unwrapped = yaw if not self._odom else self._odom[-1][1] + wrap_angle(yaw - self._last_yaw)
        self._last_yaw = yaw
        self._odom.append((stamp, unwrapped))
        while len(self._odom) > 2 and self._odom[1][0] < stamp - HISTORY:
            self._odom.popleft()
        self._process()

    def add_visual(self, stamp, yaw):
        """A visual-odometry yaw (rad) at ``stamp``; ``yaw`` None when VO is lost."""
        self._pending.append((stamp, yaw))
        while len(self._pending) > MAX_PENDING:   # no odometry is covering them
            self._pending.popleft()
        self._process()

    def _gyro_at(self, stamp):
        """Gyro yaw interpolated at ``stamp``, None if not bracketed closely enough."""
        samples = self._odom
        if not samples or stamp < samples[0][0]:
            return None
        for (ta, ya), (tb, yb) in zip(reversed(list(samples)[:-1]), reversed(samples)):
            if ta <= stamp <= tb:
                if tb - ta > self.max_gap:
                    return None
                return ya if tb == ta else ya + (yb - ya) * (stamp - ta) / (tb - ta)
        return samples[-1][1] if stamp == samples[-1][0] else None

    def _process(self):
        while self._pending and self._odom and self._pending[0][0] <= self._odom[-1][0]:
            stamp, yaw = self._pending.popleft()
            self._visual_sample(stamp, yaw, self._gyro_at(stamp))

    def _visual_sample(self, stamp, yaw, gyro):
        last = self._last_vo
        if yaw is None or gyro is None or (last is not None and stamp <= last[0]):
            self._last_vo = self._start = None
            return
        if last is None or stamp - last[0] > self.max_gap:
            unwrapped, self._start = yaw, None
        else:
            unwrapped = last[1] + wrap_angle(yaw - last[2])
        self._last_vo = (stamp, unwrapped, yaw)
        if self._start is None:
            self._start = (stamp, unwrapped, gyro)
        elif stamp - self._start[0] >= self.window - 1e-9:
            t0, vo0, gyro0 = self._start
            self.rows.append((gyro - gyro0, unwrapped - vo0, stamp - t0))
            self._start = (stamp, unwrapped, gyro)

    def recording_time(self, until):
        """s from the first odometry fed (when the recording began) to ``until``; 0 before any."""
        return 0.0 if self._first_stamp is None else until - self._first_stamp


def _fit(rows, with_scale):
    """Least squares of ``gyro - vo = s vo + b dt``: (b, s, std_b, std_s, residuals), None if singular."""
    n = len(rows)
    ys = [g - v for g, v, _ in rows]
    stt = sum(dt * dt for _, _, dt in rows)
    sty = sum(dt * y for (_, _, dt), y in zip(rows, ys))
    if not with_scale:
        bias = sty / stt
        residuals = [y - bias * dt for (_, _, dt), y in zip(rows, ys)]
        sigma2 = sum(r * r for r in residuals) / max(n - 1, 1)
        return bias, 0.0, math.sqrt(sigma2 / stt), float('inf'), residuals
    svv = sum(v * v for _, v, _ in rows)
    svt = sum(v * dt for _, v, dt in rows)
    svy = sum(v * y for (_, v, _), y in zip(rows, ys))
    det = svv * stt - svt * svt
    if det <= 1e-12 * svv * stt or svv <= 0.0:
        return None
    scale = (stt * svy - svt * sty) / det
    bias = (svv * sty - svt * svy) / det
    residuals = [y - scale * v - bias * dt for (_, v, dt), y in zip(rows, ys)]
    sigma2 = sum(r * r for r in residuals) / max(n - 2, 1)
    return bias, scale, math.sqrt(sigma2 * svv / det), math.sqrt(sigma2 * stt / det), residuals


def robust_fit(rows, with_scale, outlier_k):
    """:func:`_fit` again without outliers: (b, s, std_b, std_s, windows used), None if singular."""
    fit = _fit(rows, with_scale)
    if fit is None:
        return None
    residuals = fit[4]
    spread = 1.4826 * sorted(abs(r) for r in residuals)[len(residuals) // 2]
    if spread > 0.0:
        kept = [row for row, r in zip(rows, residuals) if abs(r) <= outlier_k * spread]
        if len(kept) < len(rows) and len(kept) >= 3:
            rows, fit = kept, _fit(kept, with_scale)
            if fit is None:
                return None
    return fit[0], fit[1], fit[2], fit[3], len(rows)

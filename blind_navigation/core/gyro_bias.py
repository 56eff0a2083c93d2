"""The gyro's bias, measured each mission: against visual odometry while recording
(core/gyro_fit.py), standing still after vision loss (:class:`StandstillBias`, only as
long as the mission needs: :func:`standstill_complete`), fused by :func:`fuse_bias`."""
import math
from collections import namedtuple

from .geometry import wrap_angle

STANDSTILL_DEFAULTS = {
    'standstill_time': 120.0,    # s, the longest standstill (0: none): bias std 3.9e-5 rad/s at 50 Hz
    'heading_budget': 0.005,     # rad: it ends once bias std x the recording's duration is within this
    'standstill_min': 5.0,       # s, the shortest: the gyro's noise is measured on a few hundred samples
    'still_speed': 0.002,        # m/s, wheel speed below which the robot counts as still
    'still_rate': 0.03,          # rad/s, gyro rate below which it counts as not turning
    'still_settle': 0.5,         # s skipped at the start of each still spell
}


class BiasEstimate(namedtuple('BiasEstimate', 'bias std source')):
    """One measurement of the gyro bias (rad/s) with its standard error and where it came from."""

    __slots__ = ()


def fuse_bias(estimates):
    """Inverse-variance mean (bias, std) of BiasEstimates ((0, inf): none; exact ones win)."""
    exact = [e.bias for e in estimates if e.std == 0.0]
    if exact:
        return sum(exact) / len(exact), 0.0
    weights = [(1.0 / (e.std * e.std), e.bias) for e in estimates if math.isfinite(e.std)]
    if not weights:
        return 0.0, float('inf')
    total = sum(w for w, _ in weights)
    return sum(w * b for w, b in weights) / total, math.sqrt(1.0 / total)


class StandstillBias(object):
    """Gyro bias from the heading change while still (``params``: as :data:`STANDSTILL_DEFAULTS`)."""

    def __init__(self, params=None):
        self.still_speed, self.still_rate, self.settle = (
            float(getattr(params, name, STANDSTILL_DEFAULTS[name]))
            for name in ('still_speed', 'still_rate', 'still_settle'))
        self.duration = 0.0        # s counted so far
        self._turned = 0.0         # rad of heading change over that time
        self._rates = [0, 0.0, 0.0]  # per-interval rates: count, sum, sum of squares
        self._last = None          # last still OdomState
        self._still_since = None   # stamp the current still spell began

    def add_odometry(self, state):
        """One OdomState (stamp in s); motion ends the current spell."""
        if abs(state.v) > self.still_speed or abs(state.w) > self.still_rate:
            self._last = self._still_since = None
            return
        if self._still_since is None:
            self._still_since = state.stamp
        last, self._last = self._last, state
        if last is None or state.stamp <= last.stamp or last.stamp - self._still_since < self.settle:
            return
        dt = state.stamp - last.stamp
        turned = wrap_angle(state.yaw - last.yaw)
        self.duration += dt
        self._turned += turned
        rate = turned / dt
        self._rates = [self._rates[0] + 1, self._rates[1] + rate, self._rates[2] + rate * rate]

    def estimate(self):
        """:class:`BiasEstimate`, or None before two intervals were counted."""
        n, total, squares = self._rates
        if n < 2:
            return None
        spread = max(squares - total * total / n, 0.0) / (n - 1)
        return BiasEstimate(self._turned / self.duration, math.sqrt(spread / n),
                            'standstill %.1f s' % self.duration)


def standstill_complete(visual, standstill, recording_time, params=None):
    """True once the standstill may end: after ``standstill_time``, or ``standstill_min`` once the
    bias (fused with ``visual``) is known to ``std x recording_time <= heading_budget``."""
    longest, shortest, budget = (float(getattr(params, name, STANDSTILL_DEFAULTS[name]))
                                 for name in ('standstill_time', 'standstill_min', 'heading_budget'))
    if standstill.duration >= longest - 1e-9:
        return True
    measured = standstill.estimate()
    if standstill.duration < shortest - 1e-9 or measured is None:
        return False
    _, std = fuse_bias([e for e in (visual, measured) if e is not None])
    return std * max(recording_time, 0.0) <= budget


def standstill_timeout(params=None):
    """s after vision loss the standstill ends anyway (None: 2 x ``standstill_time`` + 5)."""
    timeout = getattr(params, 'standstill_timeout', None)
    return float(timeout) if timeout is not None else 2.0 * float(
        getattr(params, 'standstill_time', STANDSTILL_DEFAULTS['standstill_time'])) + 5.0

"""The paper's straight/curved segment classifier (3.3.2, with a ``deadband``: docs/recording.md,
"The classifier's dead-band") and the two-rate :class:`SamplingSchedule`."""
import math
from collections import deque

from .geometry import wrap_angle

STRAIGHT = 'straight'
CURVED = 'curved'

#: Default dead-band on yaw differences, rad.
DEFAULT_DEADBAND = 0.01
#: The paper's sampling periods, s: 0.5 Hz on straight segments, 1 Hz on curves.
PAPER_STRAIGHT_PERIOD = 2.0
PAPER_CURVED_PERIOD = 1.0
WINDOW = 4

#: The sampling publisher's params (back_travel_server reads ``straight_rate`` too).
SAMPLING_DEFAULTS = {
    'straight_rate': 1.0 / PAPER_STRAIGHT_PERIOD,  # Hz, the sampling rate on straight segments
    'curved_rate': 1.0 / PAPER_CURVED_PERIOD,      # Hz, the sampling rate on curved segments
    'deadband': DEFAULT_DEADBAND,                  # rad; a yaw difference this small has no sign
}


def period_of(rate, name='rate'):
    """The sampling period (s) of ``rate`` (Hz); ValueError naming ``name`` unless positive."""
    if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not rate > 0:
        raise ValueError('%s must be a positive number of Hz, got %r' % (name, rate))
    return 1.0 / rate


def _sign(diff, deadband):
    """Sign of a raw yaw difference; 0 when its wrapped size is within the dead-band."""
    if abs(wrap_angle(diff)) <= deadband or diff == 0.0:
        return 0
    return 1 if diff > 0 else -1


def classify(yaws, deadband=DEFAULT_DEADBAND):
    """Classify four consecutive yaws (rad, as measured, unwrapped or not)."""
    if len(yaws) != WINDOW:
        raise ValueError('classify needs %d yaws, got %d' % (WINDOW, len(yaws)))
    diffs = [b - a for a, b in zip(yaws, yaws[1:])]
    signs = [_sign(diff, deadband) for diff in diffs]
    if all(s > 0 for s in signs) or all(s < 0 for s in signs):
        return CURVED
    wrapped = any(math.pi <= abs(diff) <= 2.0 * math.pi for diff in diffs)
    if wrapped and 1 in signs and -1 in signs:
        return CURVED
    return STRAIGHT


class SamplingSchedule(object):
    """The next sampling period from the last four yaws (:meth:`update` at each tick;
    straight until four are known)."""

    def __init__(self, straight_period=PAPER_STRAIGHT_PERIOD,
                 curved_period=PAPER_CURVED_PERIOD, deadband=DEFAULT_DEADBAND):
        if straight_period <= 0 or curved_period <= 0:
            raise ValueError('sampling periods must be positive (straight %r, curved %r)'
                             % (straight_period, curved_period))
        if deadband < 0:
            raise ValueError('deadband must be >= 0, got %r' % deadband)
        self.straight_period = float(straight_period)
        self.curved_period = float(curved_period)
        self.deadband = float(deadband)
        self._yaws = deque(maxlen=WINDOW)
        self.segment = STRAIGHT

    @property
    def period(self):
        """The period in force for the next cycle, s."""
        return self.curved_period if self.segment == CURVED else self.straight_period

    def update(self, yaw):
        """Add the yaw of this tick; return the period for the next cycle."""
        self._yaws.append(yaw)
        if len(self._yaws) == WINDOW:
            self.segment = classify(list(self._yaws), self.deadband)
        return self.period

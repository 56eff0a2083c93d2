"""The low-battery watch: :class:`BatteryWatch` says when a Kobuki battery is below
``battery_low`` (V), by the running median of its readings held ``battery_hold`` s, which
starts the return. docs/safety.md, "Low battery"."""
import math

#: The watch's constants (see the module docstring; docs/safety.md says why these).
BATTERY_DEFAULTS = {
    'battery_window': 5,        # readings in the running median
    'battery_hold': 2.0,        # s the median stays below battery_low before it counts
    'battery_hysteresis': 0.2,  # V above battery_low the median must rise before low clears
    'battery_stale': 2.0,       # s without a valid reading: the evidence so far is dropped
}
#: V a Kobuki battery reading can be (4S Li-ion: 16.8 V full, its cutoff above 12 V).
PLAUSIBLE = (10.0, 20.0)


def reading_problem(volts):
    """Why ``volts`` is no battery voltage, or None."""
    if volts is None or not isinstance(volts, (int, float)) or not math.isfinite(volts):
        return 'not a number (%r)' % (volts,)
    if volts == 0:
        return 'no reading (0 V: the base reports none)'
    if not PLAUSIBLE[0] <= volts <= PLAUSIBLE[1]:
        return '%.1f V is outside %.0f-%.0f V' % (volts, PLAUSIBLE[0], PLAUSIBLE[1])
    return None


class BatteryWatch(object):
    """``low`` (with ``reason``) when the median ``level`` (V) is below ``threshold``; ``ignored``."""

    def __init__(self, threshold=0.0, **settings):
        self.threshold = float(threshold or 0.0)
        self.settings = dict(BATTERY_DEFAULTS, **settings)
        self.readings, self.last = [], None     # the median's window; time of the last valid one
        self.below_since, self.below_count = None, 0
        self.low, self.reason, self.level = False, None, None
        self.ignored, self.problem = 0, None

    def update(self, now, volts):
        """A reading ``volts`` (V; None: none came) at ``now`` (s): :attr:`reason` after it."""
        if not self.threshold > 0 or volts is None:
            return self.reason
        problem = reading_problem(volts)
        if problem:
            self.ignored, self.problem = self.ignored + 1, problem
            return self.reason
        s = self.settings
        if self.last is not None and now - self.last > s['battery_stale']:
            self.readings, self.below_since, self.below_count = [], None, 0
        self.last = now
        self.readings = (self.readings + [float(volts)])[-s['battery_window']:]
        if len(self.readings) < s['battery_window']:
            return self.reason
        self.level = sorted(self.readings)[len(self.readings) // 2]
        self._decide(now)
        return self.reason

    def _decide(self, now):
        s = self.settings
        if self.low:
            if self.level >= self.threshold + s['battery_hysteresis'] - 1e-9:
                self.low, self.reason, self.below_since, self.below_count = False, None, None, 0
            return
        if self.level >= self.threshold - 1e-9:
            self.below_since, self.below_count = None, 0
            return
        if self.below_since is None:
            self.below_since = now
        self.below_count += 1
        held = now - self.below_since
        if held >= s['battery_hold'] - 1e-9 and self.below_count >= s['battery_window']:
            self.low = True
            self.reason = 'battery low: %.1f V below battery_low %.1f V for %.1f s' % (
                self.level, self.threshold, held)

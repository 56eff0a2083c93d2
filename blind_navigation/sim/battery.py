"""The fake Kobuki's battery: a voltage that drains with time and with motion, read as
kobuki_msgs/SensorState's ``battery`` (uint8, 0.1 V) and ``charger``.

Model (docs/fake_turtlebot.md, "Battery"): the voltage falls linearly at ``drain`` V/h
standing, times ``1 + motion x speed / MAX_V`` while driving (speed: the wheels' mean
|speed|, |v| + HALF_TRACK |w|); each reading adds Gaussian noise of std ``noise`` V, then
rounds to 0.1 V as the Kobuki reports it. The Kobuki driver's own levels: 16.5 V full
(battery_capacity), 14.0 V low, 13.2 V dangerous (kobuki_driver's defaults). ``charger``
is :data:`DISCHARGING` unless a dock model sets it (``charging``).
"""
import random

from .kobuki import MAX_V

#: kobuki_driver's levels, V
FULL, LOW, DANGEROUS = 16.5, 14.0, 13.2
#: kobuki_msgs/SensorState charger values
DISCHARGING, DOCKING_CHARGED, DOCKING_CHARGING = 0, 2, 6
#: m, half the Kobuki's wheel separation (0.23 m)
HALF_TRACK = 0.115
#: The battery's params (fake_kobuki's ``~battery*``)
SIM_BATTERY_DEFAULTS = {
    'battery': FULL,            # V at start
    'battery_drain': 0.6,       # V/h standing: the 2200 mAh pack's 3.3 V (full to dangerous)
                                # in 3 h of use, about half of it driving (Kobuki: 3 h small pack)
    'battery_motion': 2.0,      # at MAX_V the drain is 1 + this times the standing drain
    'battery_noise': 0.0,       # V, std of each reading's noise (0: exact)
}


class SimBattery(object):
    """``volts`` (true, V) drained by :meth:`step`; :meth:`reading` is the reported one."""

    def __init__(self, volts=FULL, drain=SIM_BATTERY_DEFAULTS['battery_drain'],
                 motion=SIM_BATTERY_DEFAULTS['battery_motion'], noise=0.0, seed=0):
        if not 0.0 <= volts <= 25.5 or drain < 0 or motion < 0 or noise < 0:
            raise ValueError('battery: volts in 0-25.5 V, drain, motion and noise >= 0 '
                             '(got %r, %r, %r, %r)' % (volts, drain, motion, noise))
        self.volts, self.drain, self.motion, self.noise = float(volts), drain, motion, noise
        self.charger = DISCHARGING      # a dock model's hook: DOCKING_CHARGING / _CHARGED
        self._random = random.Random(seed)

    def step(self, dt, v=0.0, w=0.0):
        """``dt`` s at (v, w) (m/s, rad/s) pass."""
        speed = abs(v) + HALF_TRACK * abs(w)
        rate = self.drain / 3600.0 * (1.0 + self.motion * speed / MAX_V)
        self.volts = max(0.0, self.volts - rate * dt)

    def reading(self):
        """The reported battery: uint8 in 0.1 V (noisy with ``noise``)."""
        noisy = self.volts + (self._random.gauss(0.0, self.noise) if self.noise else 0.0)
        return min(255, max(0, int(round(noisy * 10.0))))

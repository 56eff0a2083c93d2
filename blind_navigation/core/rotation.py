"""Closed-loop in-place rotation by pi on odometry yaw (paper 3.4): :class:`Rotation` commands
``w = sign(r) clamp(min(gain |r|, sqrt(2 decel |r|)), min_w, max_w)`` of the remaining angle
``r``; a turn that hunts goes on in pulses (docs/back_travel.md, "The sequence")."""
import math

from .geometry import wrap_angle

#: Defaults; the rotate_pi node exposes each one as a ~private param.
ROTATION_DEFAULTS = {
    'angle': math.pi,        # rad to turn; positive = counter-clockwise
    'max_w': 0.6,            # rad/s, cruise turn rate
    'min_w': 0.08,           # rad/s, slowest useful command (overcomes deadband/friction)
    'gain': 1.5,             # 1/s, proportional part of the deceleration
    'decel': 0.5,            # rad/s^2, braking the profile plans for
    'tolerance': 0.01,       # rad, |angle - turned| accepted
    'settle_w': 0.02,        # rad/s, measured |w| below which the robot counts as stopped
    'time_allowance': 30.0,  # s from start to done, else failed
}
#: reversals of the turn's direction after which it goes on in pulses
HUNTING = 2
#: s added to the wait after a pulse (twice the response delay measured)
PULSE_WAIT = 0.2


def turn_problem(start_yaw, yaw, tolerance):
    """Why a robot at ``yaw`` has not really turned by pi from ``start_yaw`` (within
    ``tolerance``, rad), or None; a missing ``yaw`` is a problem, a missing start is not."""
    if yaw is None:
        return 'no odometry to check the turn'
    if start_yaw is None:
        return None
    turned = abs(wrap_angle(yaw - start_yaw))
    if abs(turned - math.pi) > tolerance:
        return 'the robot turned %.2f rad since vision loss, not pi' % turned
    return None


class Rotation(object):
    """Turn in place by ``angle`` (rad) using odometry yaw; ``params``, ``overrides``:
    :data:`ROTATION_DEFAULTS`' names (missing ones take the default)."""

    def __init__(self, params=None, **overrides):
        for name, default in ROTATION_DEFAULTS.items():
            setattr(self, name, float(overrides.get(name, getattr(params, name, default))))
        if self.max_w <= 0 or self.min_w < 0 or self.min_w > self.max_w:
            raise ValueError('rotation: need 0 <= min_w <= max_w and max_w > 0 (min_w %r, max_w %r)'
                             % (self.min_w, self.max_w))
        if self.tolerance <= 0 or self.time_allowance <= 0:
            raise ValueError('rotation: tolerance and time_allowance must be positive (%r, %r)'
                             % (self.tolerance, self.time_allowance))
        self.turned, self.done, self.failed, self._start_stamp = 0.0, False, False, None

    remaining = property(lambda self: self.angle - self.turned)     # rad still to turn (signed)

    def start(self, odom_state):
        """Begin the turn from the pose in ``odom_state``."""
        self.turned, self.done, self.failed = 0.0, False, False
        self._last_yaw, self._start_stamp = odom_state.yaw, odom_state.stamp
        self._commanded_at = self.delay = None   # s: the first command's stamp, the base's delay
        self._sign, self.reversals, self._pulse = 0.0, 0, None    # _pulse: (end, wait end, w)

    def hold(self, seconds):
        """The turn was held (no odometry) for ``seconds``: they do not count against
        ``time_allowance``."""
        self._start_stamp += seconds

    def step(self, odom_state):
        """Return ``(v, w)`` for this cycle (v is always 0); sets done/failed."""
        if self._start_stamp is None:
            raise RuntimeError('Rotation.step called before start')
        self.turned += wrap_angle(odom_state.yaw - self._last_yaw)
        self._last_yaw = odom_state.yaw
        if self.done or self.failed:
            return 0.0, 0.0
        if odom_state.stamp - self._start_stamp > self.time_allowance:
            self.failed = True
            return 0.0, 0.0
        error = self.remaining
        if abs(error) <= self.tolerance:
            if abs(odom_state.w) <= self.settle_w:
                self.done = True
            return 0.0, 0.0
        t = odom_state.stamp
        if self._commanded_at is None:
            self._commanded_at = t
        elif self.delay is None and abs(odom_state.w) > self.settle_w:
            self.delay = t - self._commanded_at
        if math.copysign(1.0, error) != self._sign:
            self.reversals += self._sign != 0.0
            self._sign = math.copysign(1.0, error)
        if self.reversals >= HUNTING:
            return 0.0, self._pulsed(t, error, abs(odom_state.w))
        speed = min(self.gain * abs(error), math.sqrt(2.0 * self.decel * abs(error)))
        speed = min(self.max_w, max(self.min_w, speed))
        return 0.0, math.copysign(speed, error)

    def _pulsed(self, t, error, measured_w):
        """A hunting turn's command: a pulse of ``min_w`` for ``|error| / min_w`` s, then zero
        until twice the measured delay has passed and the robot has settled; then the next."""
        if self._pulse is not None and t < self._pulse[1]:
            return self._pulse[2] if t < self._pulse[0] else 0.0
        if measured_w > self.settle_w:
            return 0.0
        end = t + abs(error) / self.min_w
        self._pulse = (end, end + 2.0 * (self.delay or 0.0) + PULSE_WAIT, math.copysign(self.min_w, error))
        return self._pulse[2]

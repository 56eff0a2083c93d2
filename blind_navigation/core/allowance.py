"""Allowances of the closed-loop return that measure progress, and the odometry grace.

:class:`ProgressWatch`: the return fails only when it stops making progress (``stall_*``)
or spends the whole return's allowance; held time (a gap over ``max_step_gap``) is not
counted. :class:`OdomGrace`: each cycle ``drive``, ``hold`` (stale odometry: zero, keep
the goal) or ``abort`` (stale beyond ``odom_grace``). Plain Python, any one clock.
"""
import math

#: Defaults (the back-travel nodes expose them as ~params).
ALLOWANCE_DEFAULTS = {
    'stall_timeout': 10.0,          # s without progress before the return fails
    'stall_distance': 0.005,        # m of along-route progress that counts as progress
    'stall_angle': 0.01,            # rad of heading progress that counts as progress
    'return_timeout_factor': 3.0,   # whole return: factor x nominal time ...
    'return_timeout_margin': 30.0,  # ... + margin, s
    'max_step_gap': 0.5,            # s; a longer gap between control steps is held time
    'odom_timeout': 0.4,            # s; older odometry is stale: hold (zero velocity)
    'odom_grace': 5.0,              # s a hold may last before the return aborts; a hold starts
                                    # odom_timeout after the last odometry, so an odometry gap of
                                    # 3 s holds 3 s - odom_timeout, with room for a CPU stall on top
}


def allowance_param(params, name):
    """``params.name`` (or the default), checked to be a number > 0."""
    value = float(getattr(params, name, ALLOWANCE_DEFAULTS[name]) if params is not None
                  else ALLOWANCE_DEFAULTS[name])
    if not value > 0:
        raise ValueError('%s must be > 0, got %r' % (name, value))
    return value


class ProgressWatch(object):
    """Stall and whole-return allowance of one return (see module docstring).
    ``nominal_time``: the return's nominal duration, s."""

    def __init__(self, nominal_time, params=None):
        if not nominal_time >= 0 or not math.isfinite(nominal_time):
            raise ValueError('nominal_time must be a finite number >= 0, got %r' % (nominal_time,))
        self.stall_timeout = allowance_param(params, 'stall_timeout')
        self.stall_distance = allowance_param(params, 'stall_distance')
        self.stall_angle = allowance_param(params, 'stall_angle')
        self.max_step_gap = allowance_param(params, 'max_step_gap')
        self.allowance = (allowance_param(params, 'return_timeout_factor') * nominal_time
                          + allowance_param(params, 'return_timeout_margin'))
        self.active = 0.0           # s counted (held gaps left out)
        self.held = 0.0             # s of gaps left out
        self._last = None
        self._best_along = -math.inf
        self._best_heading = math.inf
        self._progress_at = 0.0

    def new_heading_goal(self):
        """A new turn (or realignment) starts: its heading error is measured afresh."""
        self._best_heading = math.inf

    def update(self, now, along, heading_error=None):
        """Record the state at ``now``: ``along`` (m along the route) and, while
        turning, ``heading_error`` (rad still to turn). Returns None, or why the
        return must fail."""
        if self._last is not None:
            gap = now - self._last
            if gap > self.max_step_gap:
                self.held += gap
            elif gap > 0:
                self.active += gap
        self._last = now
        if along >= self._best_along + self.stall_distance:
            self._best_along = along
            self._progress_at = self.active
        if heading_error is not None and heading_error <= self._best_heading - self.stall_angle:
            self._best_heading = heading_error
            self._progress_at = self.active
        if self.active - self._progress_at > self.stall_timeout:
            return ('no progress for %.1f s (stall_timeout) at %.2f m along the route'
                    % (self.active - self._progress_at, max(self._best_along, 0.0)))
        if self.active > self.allowance:
            return 'return allowance %.0f s spent at %.2f m along the route' % (
                self.allowance, max(self._best_along, 0.0))
        return None


DRIVE, HOLD, ABORT = 'drive', 'hold', 'abort'


class OdomGrace(object):
    """Hold / continue / abort from the odometry's age (see module docstring)."""

    def __init__(self, params=None):
        self.odom_timeout = allowance_param(params, 'odom_timeout')
        self.odom_grace = allowance_param(params, 'odom_grace')
        self.holding_since = None
        self.holds = []             # (start, length) of every finished hold

    def check(self, now, odom_stamp):
        """``(decision, message)`` at ``now`` for odometry stamped ``odom_stamp``
        (None: none yet). ``message`` says when a hold starts, ends (with its
        length) or turns into an abort; None otherwise."""
        age = math.inf if odom_stamp is None else now - odom_stamp
        if age <= self.odom_timeout:
            if self.holding_since is None:
                return DRIVE, None
            length = now - self.holding_since
            self.holds.append((self.holding_since, length))
            self.holding_since = None
            return DRIVE, 'odometry back after a %.2f s hold' % length
        if self.holding_since is None:
            self.holding_since = now
            return HOLD, ('odometry %s: holding (zero velocity) for up to %.1f s (odom_grace)'
                          % ('missing' if odom_stamp is None else 'older than %.2f s' % self.odom_timeout,
                             self.odom_grace))
        if now - self.holding_since > self.odom_grace:
            return ABORT, ('odometry stale for %.2f s, longer than odom_grace %.1f s'
                           % (now - self.holding_since, self.odom_grace))
        return HOLD, None

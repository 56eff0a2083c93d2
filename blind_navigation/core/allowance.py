"""The return's allowances: :class:`ProgressWatch` (fails on no progress or the whole return's
allowance spent) and :class:`OdomGrace` (drive, hold or abort on stale odometry)."""
import math

#: Defaults of the allowances.
ALLOWANCE_DEFAULTS = {
    'stall_timeout': 10.0,          # s without progress before the return fails
    'stall_distance': 0.005,        # m of along-route progress that counts as progress
    'stall_angle': 0.01,            # rad of heading progress that counts as progress
    'return_timeout_factor': 3.0,   # whole return: factor x nominal time ...
    'return_timeout_margin': 30.0,  # ... + margin, s
    'max_step_gap': 0.5,            # s; a longer gap between control steps is held time
    'odom_timeout': 0.4,            # s; older odometry is stale: hold (zero velocity)
    'odom_grace': 5.0,              # s a hold may last before the return aborts
}


def allowance_param(params, name):
    """``params.name`` (or the default), checked to be a number > 0."""
    value = float(getattr(params, name, ALLOWANCE_DEFAULTS[name]))
    if not value > 0:
        raise ValueError('%s must be > 0, got %r' % (name, value))
    return value


class ProgressWatch(object):
    """Stall and whole-return allowance of a return of ``nominal_time`` s (held gaps not counted)."""

    def __init__(self, nominal_time, params=None):
        if not nominal_time >= 0 or not math.isfinite(nominal_time):
            raise ValueError('nominal_time must be a finite number >= 0, got %r' % (nominal_time,))
        for name in ('stall_timeout', 'stall_distance', 'stall_angle', 'max_step_gap'):
            setattr(self, name, allowance_param(params, name))
        self.allowance = (allowance_param(params, 'return_timeout_factor') * nominal_time
                          + allowance_param(params, 'return_timeout_margin'))
        self.active = self.held = 0.0     # s counted, s of gaps left out
        self._last, self._best_along, self._best_heading, self._progress_at = None, -math.inf, math.inf, 0.0

    def new_heading_goal(self):
        self._best_heading = math.inf

    def update(self, now, along, heading_error=None):
        """Record ``along`` (m) and ``heading_error`` (rad, turning) at ``now``; None or why it fails."""
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
    """Drive, hold (zero velocity) or abort from the odometry's age; ``hold(seconds)``: told
    each finished hold's length."""

    def __init__(self, params=None, hold=None):
        self.odom_timeout, self.odom_grace = (allowance_param(params, name) for name in ('odom_timeout', 'odom_grace'))
        self.holding_since, self.hold = None, hold or (lambda seconds: None)

    def check(self, now, odom_stamp):
        """``(decision, message)`` at ``now`` for odometry stamped ``odom_stamp`` (None: none);
        ``message`` when a hold starts, ends or turns into an abort."""
        age = math.inf if odom_stamp is None else now - odom_stamp
        if age <= self.odom_timeout:
            if self.holding_since is None:
                return DRIVE, None
            length = now - self.holding_since
            self.holding_since = None
            self.hold(length)       # held time is not driving time
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

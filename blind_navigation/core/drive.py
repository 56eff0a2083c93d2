"""How a drive ends (typed :class:`Outcome`) and each cycle's odometry check of a drive
(:class:`DriveCycle`: fresh, held within the grace, or lost); docs/back_travel.md, "The drive
loop"."""
import collections

from . import outcome
from .allowance import ABORT, HOLD, OdomGrace

SUCCEEDED, CANCELLED, FAILED, TIMED_OUT = 'succeeded', 'cancelled', 'failed', 'timed out'
SAFETY_STOP, ODOMETRY_LOST, PREEMPTED = 'safety stop', 'odometry lost', 'preempted'
TAKEN_OVER = 'taken over'      # an operator took the robot (on_takeover abort)

#: The core/outcome code of a kind, where the Outcome names none.
KIND_CODES = {SUCCEEDED: outcome.NONE, CANCELLED: outcome.CANCELLED, FAILED: outcome.ROLE_FAILURE,
              TIMED_OUT: outcome.TIMEOUT, SAFETY_STOP: outcome.SAFETY_EVENT, ODOMETRY_LOST: outcome.ODOMETRY,
              PREEMPTED: outcome.CANCELLED, TAKEN_OVER: outcome.TAKEOVER}


class Outcome(collections.namedtuple('Outcome', 'kind reason code', defaults=(outcome.NONE,))):
    """How a behaviour ended: ``kind`` (one of the names above), why, and where the kind
    does not say it, the core/outcome ``code`` of the cause."""
    __slots__ = ()

    ok = property(lambda self: self.kind == SUCCEEDED)

    @property
    def cause(self):
        """The core/outcome code: ``code``, else the kind's (:data:`KIND_CODES`)."""
        return self.code or KIND_CODES[self.kind]


class DriveCycle(object):
    """One cycle's odometry check of a drive; ``grace_params`` (odom_timeout, odom_grace) or
    None: stale odometry ends the drive at once; ``hold(seconds)``: told each hold's length."""

    def __init__(self, grace_params=None, odom_timeout=None, hold=None):
        self.grace = OdomGrace(grace_params, hold) if grace_params is not None else None
        self.odom_timeout = odom_timeout

    def decide(self, now, odom_stamp):
        """``(decision, message)``: an Outcome to end, HOLD (publish zero this cycle)
        or None (step); ``message``: an odometry hold started, ended or failed."""
        if self.grace is None:
            stale = odom_stamp is None or now - odom_stamp > self.odom_timeout
            return (Outcome(ODOMETRY_LOST, 'odometry stale'), None) if stale else (None, None)
        decision, message = self.grace.check(now, odom_stamp)
        if decision == ABORT:
            return Outcome(ODOMETRY_LOST, message), message
        return (HOLD if decision == HOLD else None), message

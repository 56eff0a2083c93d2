"""The drive loop's logic without ROS: typed outcomes, the behaviour API, one cycle.

A :class:`Behaviour` (the pi turn, a back-travel goal, a calibration spin) has
``start``, ``step(odom, now)`` -> ``(v, w)`` or an :class:`Outcome`, ``end`` and ``hold``.
:class:`DriveCycle` decides each cycle: the behaviour's end, a safety stop, a cancel, the
mission leaving its state, the odometry grace. Run by ros/drive_loop.DriveLoop
(docs/back_travel.md, "The drive loop").
"""
import collections

from . import outcome
from .allowance import ABORT, HOLD, OdomGrace

SUCCEEDED, CANCELLED, FAILED, TIMED_OUT = 'succeeded', 'cancelled', 'failed', 'timed out'
SAFETY_STOP, ODOMETRY_LOST, PREEMPTED = 'safety stop', 'odometry lost', 'preempted'
TAKEN_OVER = 'taken over'      # an operator took the robot (on_takeover abort)


#: The core/outcome code of a kind, where the Outcome names none.
KIND_CODES = {SUCCEEDED: outcome.NONE, CANCELLED: outcome.CANCELLED, FAILED: outcome.ROLE_FAILURE,
              TIMED_OUT: outcome.TIMEOUT, SAFETY_STOP: outcome.SAFETY_EVENT,
              ODOMETRY_LOST: outcome.ODOMETRY, PREEMPTED: outcome.CANCELLED,
              TAKEN_OVER: outcome.TAKEOVER}


class Outcome(collections.namedtuple('Outcome', 'kind reason code', defaults=(outcome.NONE,))):
    """How a behaviour ended: ``kind`` (one of the names above), why, and where the kind
    does not say it, the core/outcome ``code`` of the cause."""
    __slots__ = ()

    @property
    def ok(self):
        return self.kind == SUCCEEDED

    @property
    def cause(self):
        """The core/outcome code: ``code``, else the kind's (:data:`KIND_CODES`)."""
        return self.code or KIND_CODES[self.kind]


class Behaviour(object):
    """What the drive loop drives (module docstring); subclasses override ``step``."""

    def start(self, odom):
        """The loop starts from ``odom`` (fresh odometry)."""

    def end(self):
        """An Outcome once the behaviour is over before a cycle, else None."""
        return None

    def hold(self, seconds):
        """The robot was held still ``seconds`` for stale odometry."""

    def resumed(self, seconds):
        """A pause of ``seconds`` (a takeover, a bumper contact) ended; the robot may have moved."""
        self.hold(seconds)

    def step(self, odom, now):
        raise NotImplementedError


class DriveCycle(object):
    """One cycle's decision for ``behaviour``; ``grace_params`` (odom_timeout,
    odom_grace) or None: stale odometry ends the behaviour at once."""

    def __init__(self, behaviour, grace_params=None, odom_timeout=None):
        self.behaviour = behaviour
        self.grace = OdomGrace(grace_params) if grace_params is not None else None
        self.odom_timeout = odom_timeout

    def decide(self, now, odom_stamp, tripped=None, cancelled=False, inactive=None):
        """``(decision, message)``: an Outcome to end, HOLD (publish zero this cycle)
        or None (step); ``message``: an odometry hold started, ended or failed."""
        end = self.behaviour.end()
        if end is not None:
            return end, None
        if tripped:
            return Outcome(SAFETY_STOP, tripped), None
        if cancelled:
            return Outcome(CANCELLED, 'cancelled'), None
        if inactive:
            return Outcome(PREEMPTED, inactive), None
        if self.grace is None:
            stale = odom_stamp is None or now - odom_stamp > self.odom_timeout
            return (Outcome(ODOMETRY_LOST, 'odometry stale'), None) if stale else (None, None)
        held = len(self.grace.holds)
        decision, message = self.grace.check(now, odom_stamp)
        if decision == ABORT:
            return Outcome(ODOMETRY_LOST, message), message
        if decision == HOLD:
            return HOLD, message
        if len(self.grace.holds) > held:
            self.behaviour.hold(self.grace.holds[-1][1])   # held time is not driving time
        return None, message

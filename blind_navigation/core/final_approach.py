"""The return's ending (:class:`ReturnEnding`): the robot settles, backs to the route's end if
it stopped past it (:class:`FinalApproach`), settles again; then the home verdict
(docs/safety.md, "`home`: one invariant")."""
import math

from . import mission_state, outcome
from .allowance import ABORT, HOLD
from .back_travel import BACK_TRAVEL_DEFAULTS, _param as back_travel_param, stopped
from .drive import DriveCycle
from .geometry import distance, wrap_angle
from .mission_drive import ZERO
from .mission_limits import PausedClock

SETTLE, APPROACH = 'settle', 'final approach'
#: The final approach's constants.
APPROACH_DEFAULTS = {
    'approach_tolerance': 0.05,   # m past the route's end (along its last segment) that starts it
    'approach_v': 0.05,           # m/s it reverses at
}
#: rad: the end farther off the robot's tail is not reached reversing.
APPROACH_ANGLE = math.pi / 3.0


def _param(params, name):
    return back_travel_param(params, name, APPROACH_DEFAULTS if name in APPROACH_DEFAULTS else BACK_TRAVEL_DEFAULTS)


class FinalApproach(object):
    """Reverses from ``odom`` to ``end`` (x, y) at ``approach_v`` by pure pursuit seen from the
    tail, until the end is no longer behind, the time is up or the robot is ``route_max_offset`` off."""

    def __init__(self, end, odom, params, now):
        self.end, self.start = end, (odom.x, odom.y)
        self.v, self.max_w = _param(params, 'approach_v'), _param(params, 'correction_w')
        self.lookahead, self.stop_lead = _param(params, 'lookahead'), _param(params, 'stop_lead')
        self.reach = _param(params, 'route_max_offset')
        self.clock = PausedClock(now)
        self.limit = _param(params, 'timeout_factor') * self.off(odom) / self.v + \
            _param(params, 'timeout_margin')
        self.cycle = DriveCycle(params)
        self.ended = ''             # why it stopped ('' while it drives)

    @classmethod
    def planned(cls, route, odom, params, now):
        """The approach if ``odom`` stopped past the ``route``'s end (along its last segment), near
        it; else None."""
        if route.vertices < 2:
            return None
        heading = route.direction(route.vertices - 2)
        past = ((odom.x - route.x[-1]) * math.cos(heading)
                + (odom.y - route.y[-1]) * math.sin(heading))
        if past <= _param(params, 'approach_tolerance'):
            return None
        approach = cls((route.x[-1], route.y[-1]), odom, params, now)
        behind, alpha = approach.bearing(odom)
        return approach if approach.off(odom) <= approach.reach and behind > 0.0 and \
            abs(alpha) <= APPROACH_ANGLE else None

    def off(self, odom):
        return distance(odom.x, odom.y, self.end[0], self.end[1])

    def bearing(self, odom):
        """(m the end is behind the robot, its bearing from the robot's tail in rad)."""
        dx, dy = self.end[0] - odom.x, self.end[1] - odom.y
        behind = -(dx * math.cos(odom.yaw) + dy * math.sin(odom.yaw))
        return behind, wrap_angle(math.atan2(dy, dx) - odom.yaw - math.pi)

    def resumed(self, seconds):
        self.clock.resumed(seconds)

    def step(self, now, odom):
        """(v, w) this cycle, or None once it ended (:attr:`ended` says why)."""
        behind, alpha = self.bearing(odom)
        if behind <= abs(odom.v) * self.stop_lead:
            self.ended = 'at the end'
        elif self.off(odom) > self.reach:
            self.ended = '%.2f m from the end (route_max_offset %.2f m)' % (self.off(odom), self.reach)
        elif self.clock.elapsed(now) > self.limit:
            self.ended = 'not there within %.0f s' % self.limit
        if self.ended:
            return None
        w = 2.0 * self.v * math.sin(alpha) / max(self.off(odom), self.lookahead)
        return -self.v, max(-self.max_w, min(self.max_w, w))

    def describe(self, odom):
        return 'final approach: backed %.2f m, %s' % (
            distance(odom.x, odom.y, self.start[0], self.start[1]), self.ended or 'stopped')


def home_verdict(odom, route, goals, mode, tolerance, warning=''):
    """(state, core/outcome code, reason) once every goal is done and the robot stopped at ``odom``:
    ``home`` within ``tolerance`` m of the ``route``'s end (None: the paper's modes, not checked;
    0: its distance not checked; the reason ends with the return's ``warning``), else ``aborted``."""
    warning = '; ' + warning if warning else ''
    if route is None:
        return mission_state.HOME, outcome.HOME, 'travelled %d landmarks (%s mode: not checked)%s' % (
            goals, mode, warning)
    off = distance(odom.x, odom.y, route.x[-1], route.y[-1])
    if tolerance and off > tolerance:
        return mission_state.ABORTED, outcome.NOT_HOME, (
            'every goal done, but the robot is %.2f m from the start by odometry '
            '(home_tolerance %.2f m): not home' % (off, tolerance))
    text = ('%.3f m from the start by odometry' % off if tolerance else
            '%.2f m from the start by odometry (not checked in this mode)' % off)
    return mission_state.HOME, outcome.HOME, 'travelled %d landmarks; %s%s' % (goals, text, warning)


class ReturnEnding(object):
    """The return's ending from ``now``: ``route`` None (paper modes): no approach, no position
    check; ``feed``, ``odom`` as core/mission_drive.ReturnDrive's; ``approach`` False: remote goals."""

    def __init__(self, now, params, config, route, goals, warning, feed, odom, approach=True):
        self.params, self.config, self.route, self.goals, self.warning = params, config, route, goals, warning
        self.feed, self.odom = feed, odom
        self.phase, self.until = SETTLE, now + config.settle_time
        self.approach, self.may_approach = None, approach and route is not None

    def where(self):
        return 'the final approach'

    def resumed(self, seconds):
        if self.approach is not None:
            self.approach.resumed(seconds)

    def step(self, now):
        """(command or None, verdict (state, outcome code, reason) once the mission ends or None)."""
        if self.phase == APPROACH:
            return self._approach(now)
        odom = self.odom()
        if not stopped(odom) and now < self.until - 1e-9:
            return None, None
        if self.may_approach:
            self.may_approach = False
            self.approach = FinalApproach.planned(self.route, odom, self.params, now)
            if self.approach is not None:
                self.phase = APPROACH       # it drives from the next (gated) cycle on
                return ZERO, None
        verdict = home_verdict(odom, self.route, self.goals, self.config.mode, getattr(
            self.params, 'home_tolerance', BACK_TRAVEL_DEFAULTS['home_tolerance']), self.warning)
        return ZERO, verdict if self.approach is None else \
            verdict[:2] + ('%s (%s)' % (verdict[2], self.approach.describe(odom)),)

    def _approach(self, now):
        decision, odom, message = self.feed(self.approach.cycle)
        if decision == ABORT:
            return ZERO, (mission_state.ABORTED, outcome.ODOMETRY, '%s: %s' % (self.where(), message))
        if decision == HOLD:
            return ZERO, None
        command = self.approach.step(now, odom)
        if command is None:
            self.phase, self.until = SETTLE, now + self.config.settle_time
            return ZERO, None
        return command, None

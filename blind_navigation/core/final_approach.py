"""The return's ending, after its last goal: the robot settles (stopped, or ``settle_time``
s); if it stopped past the route's end (closed_loop, driven here), :class:`FinalApproach`
backs it slowly along its own track to the end point and it settles again; then the home
verdict (core/mission_drive.home_verdict, the only place that declares ``home``).
:class:`ReturnEnding` is stepped by core/mission.Mission, whose gates (vision back, contacts,
takeovers, cancel, safety events, resets) hold the approach as they hold the return.
docs/safety.md, "`home`: one invariant".
"""
import math

from . import mission_state, outcome
from .allowance import ABORT, HOLD
from .back_travel import BACK_TRAVEL_DEFAULTS, stopped
from .drive import DriveCycle
from .geometry import distance, wrap_angle
from .mission_drive import ZERO, home_verdict
from .mission_limits import PausedClock

SETTLE, APPROACH = 'settle', 'final approach'
#: The final approach's constants (the why: docs/safety.md, "`home`: one invariant").
APPROACH_DEFAULTS = {
    'approach_tolerance': 0.05,   # m past the route's end (along its last segment) that starts it
    'approach_v': 0.05,           # m/s it reverses at
}
#: rad: the end farther off the robot's tail is not reached reversing (the follower's own
#: bound for steering onto a point without a turn in place first).
APPROACH_ANGLE = math.pi / 3.0


def _param(params, name):
    defaults = APPROACH_DEFAULTS if name in APPROACH_DEFAULTS else BACK_TRAVEL_DEFAULTS
    return float(getattr(params, name, defaults[name]))


def past_end(route, odom):
    """m the robot at ``odom`` is past ``route``'s end along its last segment (negative: short)."""
    if route is None or route.vertices < 2:
        return 0.0
    heading = route.direction(route.vertices - 2)
    return (odom.x - route.x[-1]) * math.cos(heading) + (odom.y - route.y[-1]) * math.sin(heading)


class FinalApproach(object):
    """Reverses from ``odom`` to the route's ``end`` (x, y) at ``approach_v`` (core/route_follower's
    pure pursuit, seen from the robot's tail, |w| within ``correction_w``) until the end is no
    longer behind it (coasting ``stop_lead`` s), at most timeout_factor x its nominal time +
    timeout_margin s of driving, or the robot farther than ``route_max_offset`` from the end."""

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
        """The approach when the robot at ``odom`` stopped more than ``approach_tolerance`` past the
        ``route``'s end, within ``route_max_offset`` of it, the end behind it; else None."""
        if past_end(route, odom) <= _param(params, 'approach_tolerance'):
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
        """A pause of ``seconds`` ended: not driving time."""
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


class ReturnEnding(object):
    """The return's ending from ``now`` (module docstring): ``goals`` driven, ``route`` (None: the
    paper's modes, neither approach nor position checked), the return's ``warning``; ``feed`` and
    ``odom`` as core/mission_drive.ReturnDrive's; ``approach``: False where the robot is not
    driven here (remote goals)."""

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
        """(command, verdict): the command this cycle (None: nothing); the verdict, (state, core/
        outcome code, reason) once the mission ends, else None."""
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

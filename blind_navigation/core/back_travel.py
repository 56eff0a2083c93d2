"""Back-travel control (paper 3.3.5): the paper's ``time`` and ``distance`` controllers;
``closed_loop`` is core/route_follower.py (docs/back_travel.md, "Control modes")."""
import math

from . import outcome
from .geometry import distance
from .safety import SAFETY_DEFAULTS, expected_duration

MODES = ('time', 'distance', 'closed_loop')

#: Defaults of the return's drive.
BACK_TRAVEL_DEFAULTS = {
    'straight_period': 2.0,   # s; a landmark with T >= this is a straight segment
    'max_v': 0.5,             # m/s, hard clamp on |v|
    'max_w': 1.0,             # rad/s, hard clamp on |w|
    'timeout_factor': 3.0,    # a goal's allowance = factor * expected duration + timeout_margin
    'timeout_margin': 2.0,    # s added to a goal's allowance
    'lookahead': 0.1,         # m, shortest pure-pursuit lookahead (closed_loop)
    'min_v': 0.03,            # m/s, slowest speed of distance goals, and of closed-loop sections recorded faster
    'creep_v': 0.02,          # m/s; a stretch recorded slower is driven at this (closed_loop)
    'min_d': 0.002,           # m, goals shorter than this end at once (distance)
    'stop_lead': 0.2,         # s the robot coasts after its last command (closed_loop)
    'lookahead_time': 0.5,    # s; the lookahead grows to this x the speed (closed_loop)
    'brake_decel': 0.5,       # m/s^2; slowing down towards a corner and the end (closed_loop)
    'stopped_v': 0.01,        # m/s; below this (and stopped_w) the robot counts as stopped
    'stopped_w': 0.05,        # rad/s; below this (and stopped_v) the robot counts as stopped
    'stop_timeout': 2.0,      # s; the longest wait for the robot to stop at a corner
    'align_tolerance': 0.1,   # rad; a smaller heading error at a corner is left to the pursuit
    'aim_distance': 0.1,      # m; a turn in place faces the route point this far ahead
    'correction_w': SAFETY_DEFAULTS['correction_w'],  # rad/s a section may turn beyond its recorded rate
    'route_max_offset': 0.5,  # m off the route (closed_loop): farther, the return does not rejoin it
    'finish_tolerance': 0.1,  # m from the route's end where the follower plans to stop (closed_loop)
    'home_tolerance': 0.25,   # m from the start, the robot stopped (closed_loop): else not home
    'paused_move': 0.05,      # m moved while paused (time, distance): the replay cannot go on from there
}


def stopped(odom):
    """True once ``odom`` shows the robot standing (``stopped_v``, ``stopped_w``)."""
    return odom is not None and abs(odom.v) <= BACK_TRAVEL_DEFAULTS['stopped_v'] and \
        abs(odom.w) <= BACK_TRAVEL_DEFAULTS['stopped_w']


def _param(params, name, defaults=BACK_TRAVEL_DEFAULTS):
    return float(getattr(params, name, defaults[name]))


def replay_command(landmark, straight_period):
    """The paper's command for ``landmark``: ``(v, 0)`` straight, ``(v, -w)`` curved."""
    if landmark.T >= straight_period - 1e-6:
        return landmark.v, 0.0
    return landmark.v, -landmark.w


class Odometer(object):
    """What a drive ``travelled`` on odometry (moved while paused: ``displaced``)."""

    displaced = 0.0
    _resync = False

    def pause_ended(self):
        """A pause ended: the next step's motion is not the drive's."""
        self._resync = True

    def _count_step(self, odom_state):
        """Count the step to ``odom_state``; True once the drive is done or failed."""
        step = distance(self._last.x, self._last.y, odom_state.x, odom_state.y)
        if self._resync:
            self._resync = False
            self.displaced += step
            self.moved_while_paused(step)
        else:
            self.travelled += step
        self._last = odom_state
        return self.done or self.failed

    def moved_while_paused(self, metres):
        pass


class _Controller(Odometer):
    """A paper-mode goal: one landmark replayed within its time allowance."""

    def __init__(self, landmark, params):
        self.landmark = landmark
        self.max_v, self.max_w = _param(params, 'max_v'), _param(params, 'max_w')
        self.straight_period = _param(params, 'straight_period')
        self.allowance = (_param(params, 'timeout_factor') * self.expected_duration()
                          + _param(params, 'timeout_margin'))
        self.paused_move = _param(params, 'paused_move')
        self.travelled, self.done, self.failed, self.reason = 0.0, False, False, ''
        self.code = outcome.NONE    # core/outcome's cause once failed
        self.started = self._last = None

    def expected_duration(self):
        return self.landmark.T

    def moved_while_paused(self, metres):
        """A replay goes on only from where it paused: moved farther, it fails."""
        if metres > self.paused_move:
            self.failed, self.code = True, outcome.OFF_ROUTE
            self.reason = ('the robot was moved %.2f m while the return was paused (a takeover or a '
                           'contact): the %s mode replays landmarks and cannot rejoin the path from '
                           'there' % (metres, self.MODE))

    def elapsed(self, odom_state):
        return odom_state.stamp - self.started

    def start(self, odom_state):
        self.started, self._last, self.travelled = odom_state.stamp, odom_state, 0.0
        self.done = self.failed = False
        self.reason = ''

    def hold(self, seconds):
        """The goal's clock skips the ``seconds`` held."""
        if self.started is not None:
            self.started += seconds

    def resumed(self, seconds):
        self.hold(seconds)
        self.pause_ended()

    def step(self, odom_state):
        if self.started is None:
            raise RuntimeError('%s.step called before start' % type(self).__name__)
        if self._count_step(odom_state):
            return 0.0, 0.0
        if self.elapsed(odom_state) > self.allowance:
            self.failed, self.code = True, outcome.TIMEOUT
            self.reason = 'time allowance %.1f s exceeded after %.3f m of %.3f m' % (
                self.allowance, self.travelled, self.landmark.d)
            return 0.0, 0.0
        v, w = self.command(odom_state)
        if self.done:
            return 0.0, 0.0
        return max(-self.max_v, min(self.max_v, v)), max(-self.max_w, min(self.max_w, w))

    def command(self, odom_state):
        raise NotImplementedError


class TimeController(_Controller):
    """The paper's sampled-time control: the replayed velocity for ``T``."""

    MODE = 'time'

    def command(self, odom_state):
        if self.elapsed(odom_state) >= self.landmark.T - 1e-9:
            self.done = True
        return replay_command(self.landmark, self.straight_period)


class DistanceController(_Controller):
    """The paper's travelled-distance control: the replayed velocity (|v| >= ``min_v``) until ``d``."""

    MODE = 'distance'

    def __init__(self, landmark, params):
        self.min_v = _param(params, 'min_v')
        super(DistanceController, self).__init__(landmark, params)
        v, self.w_command = replay_command(landmark, self.straight_period)
        self.v_command = math.copysign(max(abs(v), self.min_v), v)
        self.min_d = _param(params, 'min_d')

    def expected_duration(self):
        return expected_duration(self.landmark, self.min_v)

    def command(self, odom_state):
        if self.travelled >= self.landmark.d or self.landmark.d < self.min_d:
            self.done = True
        return self.v_command, self.w_command

"""Plausibility rules: what no Kobuki can do is refused: :class:`Limits` (a landmark),
:class:`OdometryGate` (successive odometry states), :class:`RouteBudget` (the return's
distance); the margins: docs/safety.md, "Plausibility margins"."""
import math
from collections import namedtuple

from .geometry import wrap_angle

#: Kobuki's velocity limits (kobuki_node): 0.7 m/s, pi rad/s.
KOBUKI_MAX_V = 0.7
KOBUKI_MAX_W = math.pi

PLAUSIBILITY_DEFAULTS = {
    'max_v': KOBUKI_MAX_V,        # m/s
    'max_w': KOBUKI_MAX_W,        # rad/s
    'speed_margin': 0.1,          # fraction beyond max_v / max_w still accepted
    'time_slack': 0.25,           # s added to T when bounding a landmark's d
    'position_jitter': 0.02,      # m an odometry step may exceed max_v x dt by
    'yaw_jitter': 0.02,           # rad a yaw step may exceed max_w x dt by
    'reanchor_time': 1.0,         # s of self-consistent refused states before re-anchoring (> 0)
    'route_length_factor': 1.5,   # x the recorded route's length
    'route_length_margin': 1.0,   # m added to the route budget
}

#: Most refused states a chain keeps (only its ends beyond: its stamps do not advance).
CHAIN_CAP = 2000


def nonnegative_param(params, name, defaults, what):
    """Param ``name`` of ``params`` (dict, object or None) as a float, finite and >= 0."""
    if isinstance(params, dict):
        value = params.get(name, defaults[name])
    else:
        value = getattr(params, name, defaults[name])
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ValueError('%s parameter %s must be a finite number >= 0, got %r'
                         % (what, name, value))
    return value


def _param(params, name):
    return nonnegative_param(params, name, PLAUSIBILITY_DEFAULTS, 'plausibility')


def _jumped(what, amount, dt, rate, jitter, unit):
    """Why ``amount`` (``unit``) in ``dt`` s is more than ``rate`` per s + ``jitter``, or None."""
    most = rate * dt + jitter
    if amount > most:
        return ('odometry %s jumped %.3g %s in %.3f s (at most %.3g %s: %g %s/s x dt + %g %s)'
                % (what, amount, unit, dt, most, unit, rate, unit, jitter, unit))
    return None


class Limits(namedtuple('Limits', 'max_v max_w speed_margin time_slack', defaults=(
        KOBUKI_MAX_V, KOBUKI_MAX_W, PLAUSIBILITY_DEFAULTS['speed_margin'], PLAUSIBILITY_DEFAULTS['time_slack']))):
    """The base's limits (:data:`PLAUSIBILITY_DEFAULTS`)."""

    __slots__ = ()

    top_v = property(lambda self: self.max_v * (1.0 + self.speed_margin))
    top_w = property(lambda self: self.max_w * (1.0 + self.speed_margin))

    def twist_problem(self, v, w):
        """None if ``|v|`` and ``|w|`` are within the limits, else why not."""
        for name, value, top, limit, unit in (('v', v, self.top_v, self.max_v, 'm/s'),
                                              ('w', w, self.top_w, self.max_w, 'rad/s')):
            if abs(value) > top:
                return '|%s| = %g %s exceeds the limit %g %s (+%g%%)' % (
                    name, abs(value), unit, limit, unit, 100.0 * self.speed_margin)
        return None

    def distance_problem(self, d, period):
        """None if ``d`` (m) fits what the base can cover in ``period`` (s), else why not."""
        longest = self.max_v * (period * (1.0 + self.speed_margin) + self.time_slack)
        if d > longest:
            return ('d = %g m is farther than the base can go in T = %g s (at most %g m: '
                    '%g m/s x (T x %g + %g s))' % (d, period, longest, self.max_v,
                                                    1.0 + self.speed_margin, self.time_slack))
        return None


class OdometryGate(object):
    """Refuses odometry no Kobuki can produce: :meth:`check` each state in arrival order
    (finite, the twist within the limits, the step from the last accepted state within
    ``top dt + jitter``). A refused state never becomes the reference; with ``on_reanchor``
    a self-consistent refused chain spanning ``reanchor_time`` does (docs/safety.md,
    "Odometry resets")."""

    def __init__(self, params=None, on_reanchor=None):
        self.limits = Limits(*(_param(params, name) for name in Limits._fields))
        self.position_jitter = _param(params, 'position_jitter')
        self.yaw_jitter = _param(params, 'yaw_jitter')
        self.reanchor_time = _param(params, 'reanchor_time')
        if not self.reanchor_time > 0:
            raise ValueError('reanchor_time must be > 0 s, got %r' % self.reanchor_time)
        self.on_reanchor, self.reference = on_reanchor, None
        self.refused = self.reanchors = 0     # since the gate was made
        self.refusing, self.last_refusal = False, ''    # refusing: the newest state was refused
        self._chain = []            # the refused chain's states, oldest first
        self.confirmed = False      # the reference followed an accepted state (or a chain)
        self.reanchored_from, self.reanchor_chain = None, ()   # at a re-anchor: the old reference
        # (None if unconfirmed) and the chain re-anchored on

    def reset(self, state=None, confirmed=False):
        """Forget the reference and chain; ``state`` (unchecked) becomes the reference."""
        self.reference, self.confirmed, self.refusing, self._chain = state, confirmed, False, []

    def check(self, state):
        """None if ``state`` (an OdomState-like object) is accepted, else why not."""
        problem = self._own_problem(state)
        if problem:
            return self._refuse(problem)
        if self.reference is None:
            self.reset(state)
            return None
        problem = self.step_problem(self.reference, state)
        chain = self._chain[-1] if self._chain else None
        if chain is not None and not 0.0 <= state.stamp - chain.stamp <= self.reanchor_time:
            chain, self._chain = None, []       # a stale chain is forgotten
        continues_chain = chain is not None and self.step_problem(chain, state) is None
        if problem is None and not continues_chain:
            self.reset(state, confirmed=True)
            return None
        if continues_chain:
            self._chain.append(state)
            if self.on_reanchor is None or len(self._chain) > CHAIN_CAP:
                del self._chain[1:-1]       # bounded: stamps that do not advance, no re-anchor
            problem = problem or ('continues the odometry refused since %.3f s, not the last '
                                  'accepted state (a discontinuity)' % self._chain[0].stamp)
        else:
            self._chain = [state]
        span = self._chain[-1].stamp - self._chain[0].stamp
        if self.on_reanchor is not None and span >= self.reanchor_time:
            old = self.reference
            self.reanchored_from = old if self.confirmed else None
            self.reanchor_chain = tuple(self._chain)
            self.reset(state, confirmed=True)
            self.reanchors += 1
            self.on_reanchor('odometry re-anchored: it jumped from (%.3f, %.3f) at %.3f s to '
                             '(%.3f, %.3f) and stayed consistent for %.2f s (an odometry reset?); '
                             'it was: %s' % (old.x, old.y, old.stamp, state.x, state.y, span,
                                             problem))
            return None
        return self._refuse(problem)

    def _refuse(self, problem):
        self.refused += 1
        self.refusing, self.last_refusal = True, problem
        return problem

    def _own_problem(self, state):
        for name in ('x', 'y', 'yaw', 'v', 'w', 'stamp'):
            value = getattr(state, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                return 'odometry %s is not a finite number: %r' % (name, value)
        problem = self.limits.twist_problem(state.v, state.w)
        return 'odometry twist: ' + problem if problem else None

    def step_problem(self, before, after):
        """None if ``after`` may follow ``before``, else why not."""
        dt = after.stamp - before.stamp
        if dt < 0.0:
            return 'odometry stamp went back %.3f s (from %.3f to %.3f)' % (
                -dt, before.stamp, after.stamp)
        step = math.hypot(after.x - before.x, after.y - before.y)
        turn = abs(wrap_angle(after.yaw - before.yaw))
        return (_jumped('position', step, dt, self.limits.top_v, self.position_jitter, 'm')
                or _jumped('yaw', turn, dt, self.limits.top_w, self.yaw_jitter, 'rad'))


class RouteBudget(object):
    """How far the whole return may drive: ``route_length_factor`` x the landmarks'
    ``max(d, |v| T)`` sum + ``route_length_margin``."""

    def __init__(self, landmarks, params=None):
        self.factor = _param(params, 'route_length_factor')
        self.margin = _param(params, 'route_length_margin')
        self.length = max(sum(max(lm.d, abs(lm.v) * lm.T) for lm in landmarks), 0.0)
        self.limit = self.factor * self.length + self.margin

    def problem(self, travelled):
        """None while ``travelled`` (m, across restarts) is within :attr:`limit`, else why not."""
        if not (isinstance(travelled, (int, float)) and math.isfinite(travelled)):
            return 'distance travelled is not a finite number: %r' % (travelled,)
        if travelled > self.limit:
            return ('the return drove %.2f m, more than its budget of %.2f m (%g x the recorded '
                    "route's %.2f m + %g m)" % (travelled, self.limit, self.factor, self.length,
                                               self.margin))
        return None

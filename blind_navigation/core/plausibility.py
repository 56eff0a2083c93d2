"""Plausibility rules: what no Kobuki can do is refused, whoever sends it.

:class:`Limits` (a landmark's speeds and ``d`` against ``T``), :class:`OdometryGate`
(successive odometry states: non-finite values, impossible twists or steps, stamps going
back) and :class:`RouteBudget` (the whole return's distance). The margins,
:data:`PLAUSIBILITY_DEFAULTS`: docs/safety.md, "Plausibility margins".
"""
import math
from collections import namedtuple

from .geometry import wrap_angle

#: Kobuki's velocity limits (kobuki_node): 0.7 m/s, pi rad/s.
KOBUKI_MAX_V = 0.7
KOBUKI_MAX_W = math.pi
#: kobuki_driver's acceleration limiter (kobuki_node's ``acceleration_limiter``): m/s^2 and
#: rad/s^2 speeding up (``*_up``) and slowing down (``*_down``). The closed-loop follower
#: brakes within ``v_down`` (core/back_travel ``brake_decel``).
KOBUKI_ACCEL_LIMITS = {'v_up': 0.5, 'v_down': 0.6, 'w_up': 3.5, 'w_down': 4.2}

#: Defaults (nodes expose them as ~params); units and reasons in the module docstring.
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
    """Param ``name`` of ``params`` (a dict, an object or None; ``defaults[name]`` if it
    has none) as a float; ValueError naming ``what`` unless finite and >= 0."""
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


class Limits(namedtuple('Limits', 'max_v max_w speed_margin time_slack')):
    """The base's limits: ``max_v`` (m/s), ``max_w`` (rad/s), the fraction
    ``speed_margin`` beyond them still accepted, and ``time_slack`` (s) added
    to ``T`` when bounding a landmark's ``d``."""

    __slots__ = ()

    def __new__(cls, max_v=KOBUKI_MAX_V, max_w=KOBUKI_MAX_W,
                speed_margin=PLAUSIBILITY_DEFAULTS['speed_margin'],
                time_slack=PLAUSIBILITY_DEFAULTS['time_slack']):
        return super(Limits, cls).__new__(cls, max_v, max_w, speed_margin, time_slack)

    @classmethod
    def from_params(cls, params=None):
        """Limits from ``params`` (an object or dict with the names of
        :data:`PLAUSIBILITY_DEFAULTS`; missing ones default)."""
        return cls(*(_param(params, name) for name in cls._fields))

    @property
    def top_v(self):
        """Largest |v| accepted, m/s."""
        return self.max_v * (1.0 + self.speed_margin)

    @property
    def top_w(self):
        """Largest |w| accepted, rad/s."""
        return self.max_w * (1.0 + self.speed_margin)

    def twist_problem(self, v, w):
        """None if ``|v|`` and ``|w|`` are within the limits (+ margin), else why not."""
        if abs(v) > self.top_v:
            return '|v| = %g m/s exceeds the limit %g m/s (+%g%%)' % (
                abs(v), self.max_v, 100.0 * self.speed_margin)
        if abs(w) > self.top_w:
            return '|w| = %g rad/s exceeds the limit %g rad/s (+%g%%)' % (
                abs(w), self.max_w, 100.0 * self.speed_margin)
        return None

    def max_distance(self, period):
        """Farthest a landmark of period ``period`` (s) may have gone, m."""
        return self.max_v * (period * (1.0 + self.speed_margin) + self.time_slack)

    def distance_problem(self, d, period):
        """None if ``d`` (m) fits what the base can cover in ``period`` (s), else why not."""
        longest = self.max_distance(period)
        if d > longest:
            return ('d = %g m is farther than the base can go in T = %g s (at most %g m: '
                    '%g m/s x (T x %g + %g s))' % (d, period, longest, self.max_v,
                                                    1.0 + self.speed_margin, self.time_slack))
        return None


class OdometryGate(object):
    """Refuses odometry no Kobuki can produce; see the module docstring.

    :meth:`check` each state in arrival order: None (use it) or why it is
    refused. Rules, in order:

    1. every field finite;
    2. ``|v|``, ``|w|`` within the limits (+ ``speed_margin``);
    3. against the reference (the last accepted state): the stamp not going
       back, the position step within ``top_v x dt + position_jitter`` and the
       yaw step within ``top_w x dt + yaw_jitter``.

    The position step is bounded by the base's top speed, not by the twist x
    dt: the twist is the speed at the message's time, not over ``dt``, and a
    fused or filtered odometry's twist may lag its pose.

    The first state is accepted as the reference (there is nothing to compare
    it with). A refused state never becomes the reference, so a burst of
    garbage interleaved with the real stream (finding 1: x = 1e6 at 100 Hz
    between 50 Hz real odometry) is refused message by message and the real
    messages keep being accepted. A state that continues the stream being
    refused (plausible from its newest state, which arrived at most
    ``reanchor_time`` earlier) is refused too, even once enough time has
    passed for the base to have reached it from the reference: a reset that
    jumped 0.5 m is not let in after 0.7 s.

    Re-anchor rule (only with an ``on_reanchor`` callback; without one the gate
    never re-anchors and keeps refusing, which holds whoever drives on it): a
    genuine discontinuity (an odometry reset, a restarted base driver, sim time
    reset, or a garbage first state) also looks like a jump, but afterwards the
    stream is consistent with itself and nothing consistent with the old
    reference arrives any more. So when, with no state accepted meanwhile, the
    refused states have formed one self-consistent chain (each plausible from
    the previous one by rules 1-3) spanning at least ``reanchor_time`` of its
    own stamps, its newest state becomes the reference, is accepted, and
    ``on_reanchor(reason)`` is called first. Garbage that alternates with the
    real stream, is not self-consistent, or whose stamps do not advance
    (``rostopic pub`` without a header stamp) never re-anchors; a refused
    chain with a gap longer than ``reanchor_time`` is forgotten. At a
    re-anchor, :attr:`reanchored_from` (the old reference, None if no second
    state ever confirmed it) and :attr:`reanchor_chain` (the chain's states)
    let core/odometry_reset.ResetCarrier carry the old frame across, or say
    why it cannot (then the callback's owner treats it as a discontinuity: a
    gap in the recording, an aborted return).
    """

    def __init__(self, params=None, on_reanchor=None):
        self.limits = Limits.from_params(params)
        self.position_jitter = _param(params, 'position_jitter')
        self.yaw_jitter = _param(params, 'yaw_jitter')
        self.reanchor_time = _param(params, 'reanchor_time')
        if not self.reanchor_time > 0:
            raise ValueError('reanchor_time must be > 0 s, got %r' % self.reanchor_time)
        self.on_reanchor = on_reanchor
        self.reference = None
        self.refused = 0            # refused states since the gate was made
        self.reanchors = 0          # re-anchors since the gate was made
        self.refusing = False       # the newest state was refused (the reference is older)
        self.last_refusal = ''
        self._chain = []            # the refused chain's states, oldest first
        self.confirmed = False      # the reference followed an accepted state (or a chain)
        self.reanchored_from = None     # at a re-anchor: the old reference if confirmed, else None
        self.reanchor_chain = ()        # at a re-anchor: the chain re-anchored on, oldest first

    @property
    def _chain_start(self):
        return self._chain[0] if self._chain else None

    @property
    def _chain_last(self):
        return self._chain[-1] if self._chain else None

    def reset(self, state=None, confirmed=False):
        """Forget the reference (and any refused chain); ``state``, if given,
        becomes the new reference without checks (``confirmed``: it follows a
        state that was accepted)."""
        self.reference = state
        self.confirmed = confirmed
        self.refusing = False
        self._chain = []

    def check(self, state):
        """None if ``state`` (an OdomState-like object) is accepted, else why not."""
        problem = self._own_problem(state)
        if problem:
            return self._refuse(problem)
        if self.reference is None:
            self.reset(state)
            return None
        problem = self.step_problem(self.reference, state)
        chain = self._chain_last
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
                                  'accepted state (a discontinuity)' % self._chain_start.stamp)
        else:
            self._chain = [state]
        span = self._chain_last.stamp - self._chain_start.stamp
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
        self.refusing = True
        self.last_refusal = problem
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
    """How far the whole return may drive.

    ``length``: what the recorded landmarks command, the sum over landmarks of
    ``max(d, |v| T)``: the closed-loop return drives the chords ``d``, the
    distance mode drives ``d``, the time mode drives ``|v|`` for ``T`` (never
    faster than recorded, core/safety.goal_limits); or ``route_length`` (m,
    the length of the route a follower tracks, e.g. curved between ticks) if
    that is longer. ``limit`` =
    ``route_length_factor`` x ``length`` + ``route_length_margin``: the factor
    covers the pursuit's corrections and the replay modes' overshoot, the
    margin rejoining the route from where a resumed return stands (up to
    ``resume_max_offset``) and the last goal's coasting. :meth:`problem` gives
    the reason to stop once the distance travelled so far exceeds it.
    """

    def __init__(self, landmarks, params=None, route_length=0.0):
        self.factor = _param(params, 'route_length_factor')
        self.margin = _param(params, 'route_length_margin')
        if not (math.isfinite(route_length) and route_length >= 0.0):
            raise ValueError('route_length must be a finite length >= 0 m, got %r' % (route_length,))
        self.length = max(sum(max(lm.d, abs(lm.v) * lm.T) for lm in landmarks), route_length)
        self.limit = self.factor * self.length + self.margin

    def problem(self, travelled):
        """None while ``travelled`` (m, the return's odometry distance so far,
        across restarts) is within :attr:`limit`, else why the return must stop."""
        if not (isinstance(travelled, (int, float)) and math.isfinite(travelled)):
            return 'distance travelled is not a finite number: %r' % (travelled,)
        if travelled > self.limit:
            return ('the return drove %.2f m, more than its budget of %.2f m (%g x the recorded '
                    "route's %.2f m + %g m)" % (travelled, self.limit, self.factor, self.length,
                                               self.margin))
        return None

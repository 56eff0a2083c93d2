"""An odometry reset carried across: :func:`estimate_reset` gives the :class:`Frame` mapping
the new frame onto the old one, or why it cannot be trusted (:data:`UNTRUSTED`);
:class:`ResetCarrier` applies it behind the gate (docs/safety.md, "Odometry resets")."""
import math
from collections import namedtuple

from .geometry import wrap_angle
from .plausibility import nonnegative_param

#: Defaults; docs/safety.md, "Odometry resets", says why.
RESET_DEFAULTS = {
    'reset_max_gap': 0.25,              # s between the last old-frame and the first new-frame state
    'reset_position_tolerance': 0.02,   # m the predicted position may be off
    'reset_yaw_tolerance': 0.02,        # rad the predicted yaw may be off
    'reset_twist_margin': 0.1,          # fraction of the chain's motion its twist may miss by
    'reset_speed_noise': 0.015,         # m/s a silence's two v samples may miss its mean speed by
    'reset_yaw_rate_noise': 0.006,      # rad/s its two w samples may miss its mean turn rate by
}

#: How every untrusted reset's reason begins (a recorder's gap entry, an abort).
UNTRUSTED = 'odometry reset not re-anchored'


def is_untrusted_reset(reason):
    """True if ``reason`` (a gap entry's, an abort's) names an untrusted odometry reset."""
    return str(reason).startswith(UNTRUSTED)


class Frame(namedtuple('Frame', 'x y yaw')):
    """A planar rigid transform: a pose ``p`` becomes ``R(yaw) p + (x, y)``, its yaw ``yaw`` more."""

    __slots__ = ()

    def apply(self, state):
        """``state`` moved (its twist and stamp stay)."""
        return state._replace(**self.after(Frame(state.x, state.y, state.yaw))._asdict())

    def after(self, first):
        """The Frame that applies ``first``, then this one."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return Frame(self.x + c * first.x - s * first.y, self.y + s * first.x + c * first.y,
                     wrap_angle(self.yaw + first.yaw))


IDENTITY = Frame(0.0, 0.0, 0.0)

ResetEstimate = namedtuple('ResetEstimate', 'frame reason')
ResetEstimate.__doc__ = 'frame: the Frame from the new odometry frame to the old (None: untrusted); reason.'


def advance(x, y, yaw, v, w, dt):
    """Pose (x, y, yaw) after driving at (v, w) for dt s (an arc)."""
    if abs(w * dt) < 1e-9:
        return x + v * dt * math.cos(yaw), y + v * dt * math.sin(yaw), yaw
    radius = v / w
    end = yaw + w * dt
    return (x + radius * (math.sin(end) - math.sin(yaw)),
            y - radius * (math.cos(end) - math.cos(yaw)), end)


def _params(params):
    """RESET_DEFAULTS' params by name, each ``params``' own where it has one."""
    return {key: nonnegative_param(params, key, RESET_DEFAULTS, 'odometry reset')
            for key in RESET_DEFAULTS}


def estimate_reset(before, chain, params=None):
    """The :class:`ResetEstimate` of a jump after ``before`` (old frame, or None) to ``chain``."""
    p = _params(params)
    first, last = chain[0], chain[-1]
    where = 'at %.3f s (from (%.3f, %.3f, %.3f) to (%.3f, %.3f, %.3f))' % (
        first.stamp, before.x if before else math.nan, before.y if before else math.nan,
        before.yaw if before else math.nan, first.x, first.y, first.yaw)

    def untrusted(why):
        return ResetEstimate(None, '%s %s: %s' % (UNTRUSTED, where, why))

    if before is None:
        return untrusted('nothing before it was confirmed by a second state')
    gap = first.stamp - before.stamp
    if gap < 0.0:
        return untrusted('the stamps went back %.3f s (the ROS time moved back: a restarted '
                         'simulator, or a clock set back?)' % -gap)
    if gap > p['reset_max_gap']:
        return untrusted('no odometry for %.3f s (more than %g s) while the robot may have moved'
                         ' (a restarted driver?)' % (gap, p['reset_max_gap']))
    position_doubt = 0.5 * abs(before.v - first.v) * gap
    yaw_doubt = 0.5 * abs(before.w - first.w) * gap
    if position_doubt > p['reset_position_tolerance'] or yaw_doubt > p['reset_yaw_tolerance']:
        return untrusted('the twist changed from (%.3f, %.3f) to (%.3f, %.3f) across the %.3f s '
                         'gap: the motion meanwhile is unknown' % (before.v, before.w, first.v,
                                                                  first.w, gap))
    problem = _chain_problem(chain, p)
    if problem:
        return untrusted(problem)
    x, y, yaw = advance(before.x, before.y, before.yaw, 0.5 * (before.v + first.v),
                        0.5 * (before.w + first.w), gap)
    turn = wrap_angle(yaw - first.yaw)
    c, s = math.cos(turn), math.sin(turn)
    frame = Frame(x - (c * first.x - s * first.y), y - (s * first.x + c * first.y), turn)
    return ResetEstimate(frame, 'odometry reset re-anchored %s: carried on in the old frame, the '
                         '%.3f s gap bridged with the twist (within %.3f m, %.3f rad; the new '
                         'stream followed its twist for %.2f s)' % (
                             where, gap, position_doubt, yaw_doubt, last.stamp - first.stamp))


def _chain_problem(chain, p):
    """None if the chain's poses follow its own twist, else why not."""
    x, y, yaw = chain[0].x, chain[0].y, chain[0].yaw
    path = turned = 0.0
    for a, b in zip(chain, chain[1:]):
        dt = b.stamp - a.stamp
        x, y, yaw = advance(x, y, yaw, 0.5 * (a.v + b.v), 0.5 * (a.w + b.w), dt)
        path += math.hypot(b.x - a.x, b.y - a.y)
        turned += abs(wrap_angle(b.yaw - a.yaw))
    last = chain[-1]
    off = math.hypot(last.x - x, last.y - y)
    off_yaw = abs(wrap_angle(last.yaw - yaw))
    if (off > p['reset_position_tolerance'] + p['reset_twist_margin'] * path
            or off_yaw > p['reset_yaw_tolerance'] + p['reset_twist_margin'] * turned):
        return ('the new odometry does not follow its own twist (%.3f m, %.3f rad off over '
                '%.3f m, %.3f rad)' % (off, off_yaw, path, turned))
    return None


Taken = namedtuple('Taken', 'states problem reset')
Taken.__doc__ = ('states: the states to use, oldest first (a trusted re-anchor: its chain in the old '
                 'frame); problem: why refused, or None; reset: a ResetEstimate this state completed, or None.')


class ResetCarrier(object):
    """An OdometryGate whose re-anchors carry the old frame on (``frame``: raw -> the first frame)."""

    def __init__(self, gate, params=None):
        self.gate, self.params, self.frame = gate, params, IDENTITY
        self.reset_stamp = None     # stamp (s) of the newest reset carried across, or None
        gate.on_reanchor = lambda _reason: None     # the gate re-anchors only with a callback

    def _after_silence(self, before, state):
        """None, or the untrusted ResetEstimate of a state after a silence, off where its twists say."""
        p = _params(self.params)
        if before is None or state.stamp - before.stamp <= p['reset_max_gap']:
            return None
        dt = state.stamp - before.stamp
        x, y, yaw = advance(before.x, before.y, before.yaw, 0.5 * (before.v + state.v),
                            0.5 * (before.w + state.w), dt)
        off, off_yaw = math.hypot(state.x - x, state.y - y), abs(wrap_angle(state.yaw - yaw))
        mean_v, mean_w = 0.5 * abs(before.v + state.v), 0.5 * abs(before.w + state.w)
        slack_v = (0.5 * abs(before.v - state.v) + p['reset_twist_margin'] * mean_v + p['reset_speed_noise']) * dt
        slack_w = (0.5 * abs(before.w - state.w) + p['reset_twist_margin'] * mean_w + p['reset_yaw_rate_noise']) * dt
        if off <= p['reset_position_tolerance'] + slack_v and off_yaw <= p['reset_yaw_tolerance'] + slack_w:
            return None
        return ResetEstimate(None, '%s at %.3f s: after %.3f s without odometry it is at (%.3f, '
                             '%.3f, %.3f), %.3f m and %.3f rad from where its twist says (a '
                             'restarted driver?)' % (UNTRUSTED, state.stamp, dt, state.x, state.y,
                                                     state.yaw, off, off_yaw))

    def take(self, raw):
        """The :class:`Taken` for the raw OdomState ``raw``."""
        state = self.frame.apply(raw) if self.frame != IDENTITY else raw
        reanchors, before = self.gate.reanchors, self.gate.reference
        problem = self.gate.check(state)
        if problem:
            return Taken((), problem, None)
        if self.gate.reanchors == reanchors:
            return Taken((state,), None, self._after_silence(before, state))
        estimate = estimate_reset(self.gate.reanchored_from, self.gate.reanchor_chain, self.params)
        if estimate.frame is None:
            return Taken((state,), None, estimate)      # the new frame, as it comes
        self.frame = estimate.frame.after(self.frame)
        self.reset_stamp = self.gate.reanchor_chain[0].stamp
        states = tuple(estimate.frame.apply(s) for s in self.gate.reanchor_chain)
        self.gate.reset(states[-1], confirmed=True)
        return Taken(states, None, estimate)

    def adopt(self, frame, stamp):
        """Take another carrier's ``frame`` for the reset at ``stamp``: None, 'taken' or 'restart'."""
        reference = self.gate.reference
        if self.reset_stamp is not None and stamp <= self.reset_stamp + 1e-9:
            return None
        if self.gate.refusing and (reference is None or reference.stamp < stamp):
            return None     # confirming that reset itself: it carries it across alike
        self.frame, self.reset_stamp = frame, stamp
        if reference is not None and reference.stamp >= stamp:
            self.gate.reset()
            return 'restart'
        return 'taken'

"""Seeded random missions in named categories, for testing the return on paths no one tuned for.

``random_mission(category, seed)`` -> a :class:`~.command_series.CommandSeries` (10 Hz,
open loop; same category and seed, same mission), every piece within the Kobuki's
limits, 1-150 m over the categories; :data:`LOOP_CATEGORIES` are closed plans driven on
ground truth (sim/path_tracker.py). The categories: docs/evaluation.md.
"""
import math
import random

from .command_series import CommandSeries
from .path_tracker import TrackedSeries

RATE = 10.0                 # Hz: the operator's command rate
STEP = 1.0 / RATE           # s: every piece lasts a whole number of operator ticks
MAX_V = 0.7                 # m/s, the Kobuki's limit
MAX_W = math.pi             # rad/s, the Kobuki's limit


class _Path(object):
    """Accumulates pieces ``(v, w, duration)``; durations are whole operator ticks."""

    def __init__(self, rng):
        self.rng = rng
        self.pieces = []
        self.length = 0.0
        self.v = 0.0        # the speed the last piece left the robot at (for ramps)

    def hold(self, v, w, duration):
        ticks = max(1, int(round(duration / STEP)))
        v, w = max(-MAX_V, min(MAX_V, v)), max(-MAX_W, min(MAX_W, w))
        self.pieces.append((v, w, ticks * STEP))
        self.length += abs(v) * ticks * STEP
        self.v = v

    def ramp(self, v_to, w_to, accel, w_from=0.0, w_accel=None):
        """Change speed from the current one to ``v_to`` at ``accel`` m/s^2 (and the
        turn rate from ``w_from`` to ``w_to`` at ``w_accel`` rad/s^2), one tick at a time."""
        v_from = self.v
        ticks = int(math.ceil(max(abs(v_to - v_from) / accel,
                                  abs(w_to - w_from) / w_accel if w_accel else 0.0) / STEP))
        for k in range(1, ticks):
            f = k / float(ticks)
            self.hold(v_from + f * (v_to - v_from), w_from + f * (w_to - w_from), STEP)

    def straight(self, v, length, accel=None):
        if accel:
            self.ramp(v, 0.0, accel)
        self.hold(v, 0.0, length / abs(v))

    def arc(self, v, radius, angle):
        """Arc of ``radius`` m turning by ``angle`` rad (sign = direction of turn)."""
        w = math.copysign(min(abs(v) / radius, MAX_W), angle)
        self.hold(v, w, abs(angle / w))

    def turn(self, angle, rate, accel=None):
        """Turn in place by ``angle`` rad at ``rate`` rad/s (ramped at ``accel`` rad/s^2)."""
        w = math.copysign(rate, angle)
        if accel:
            ramp_time = rate / accel
            ramp_angle = rate * ramp_time       # both ramps together
            if ramp_angle < abs(angle):
                ticks = max(1, int(round(ramp_time / STEP)))
                for k in range(1, ticks + 1):
                    self.hold(0.0, w * k / (ticks + 1.0), STEP)
                self.hold(0.0, w, (abs(angle) - ramp_angle) / rate)
                for k in range(ticks, 0, -1):
                    self.hold(0.0, w * k / (ticks + 1.0), STEP)
                self.v = 0.0
                return
        self.hold(0.0, w, abs(angle) / rate)
        self.v = 0.0

    def pause(self, duration):
        self.hold(0.0, 0.0, duration)

    def stop(self, accel=None):
        """Come to a stop: ramped (``accel`` m/s^2) or at once."""
        if accel and abs(self.v) > 0:
            self.ramp(0.0, 0.0, accel)
        self.v = 0.0

    def sign(self):
        return self.rng.choice((-1.0, 1.0))

    def uniform(self, low, high):
        return self.rng.uniform(low, high)


def _indoor_mixed(p, target):
    while p.length < target:
        kind = p.rng.random()
        if kind < 0.38:
            p.straight(p.uniform(0.1, 0.4), p.uniform(0.3, 4.0))
        elif kind < 0.68:
            p.arc(p.uniform(0.1, 0.35), p.uniform(0.3, 2.5), p.sign() * p.uniform(0.3, 3.0))
        elif kind < 0.78:
            p.turn(p.sign() * p.uniform(0.3, 3.2), p.uniform(0.3, 1.2))
        elif kind < 0.86:
            p.pause(p.uniform(0.5, 4.0))
        elif kind < 0.93:
            p.straight(-p.uniform(0.05, 0.2), p.uniform(0.2, 1.0))
        else:
            p.straight(p.uniform(0.02, 0.05), p.uniform(0.1, 0.5))
    for v in (0.15, 0.08, 0.04, 0.02):     # slowing to a stop, as a person does with the keys
        p.hold(v, 0.0, p.uniform(0.3, 1.5))


def _fast_long(p, target):
    while p.length < target:
        kind = p.rng.random()
        v = p.uniform(0.4, MAX_V)
        if kind < 0.5:
            p.straight(v, p.uniform(2.0, 15.0), accel=0.5)
        elif kind < 0.9:
            p.arc(v, p.uniform(1.0, 5.0), p.sign() * p.uniform(0.3, 2.0))
        else:
            p.stop(accel=0.5)
            p.pause(p.uniform(0.5, 3.0))
    p.stop(accel=0.5)


def _creeping(p, target):
    while p.length < target:
        kind = p.rng.random()
        v = p.uniform(0.02, 0.05)
        if kind < 0.45:
            p.straight(v, p.uniform(0.1, 1.0))
        elif kind < 0.8:
            p.arc(v, p.uniform(0.3, 1.5), p.sign() * p.uniform(0.2, 1.5))
        elif kind < 0.92:
            p.turn(p.sign() * p.uniform(0.3, 2.0), p.uniform(0.1, 0.3))
        else:
            p.pause(p.uniform(0.5, 3.0))


def _reversing(p, target):
    while p.length < target:
        kind = p.rng.random()
        v = p.uniform(0.05, 0.3)
        if kind < 0.3:
            p.straight(v, p.uniform(0.3, 2.5))
        elif kind < 0.55:
            p.straight(-v, p.uniform(0.2, 1.5))
        elif kind < 0.7:
            p.arc(-v, p.uniform(0.4, 2.0), p.sign() * p.uniform(0.3, 1.6))   # backing round a corner
        elif kind < 0.85:                                                  # three-point turn
            side = p.sign()
            p.arc(v, p.uniform(0.4, 1.0), side * p.uniform(0.5, 1.2))
            if p.rng.random() < 0.5:
                p.pause(p.uniform(0.2, 1.0))
            p.arc(-v, p.uniform(0.4, 1.0), side * p.uniform(0.5, 1.2))
            p.arc(v, p.uniform(0.4, 1.0), side * p.uniform(0.3, 1.0))
        else:
            p.arc(v, p.uniform(0.5, 2.5), p.sign() * p.uniform(0.3, 2.0))
        if p.rng.random() < 0.3:
            p.pause(p.uniform(0.2, 2.0))


def _turns_in_place(p, target):
    while p.length < target:
        p.straight(p.uniform(0.1, 0.4), p.uniform(0.3, 2.0))
        if p.rng.random() < 0.5:
            p.pause(p.uniform(0.2, 1.5))
        for _ in range(1 if p.rng.random() < 0.7 else p.rng.randint(2, 3)):
            p.turn(p.sign() * p.uniform(math.radians(30), 2 * math.pi), p.uniform(0.3, MAX_W),
                   accel=p.uniform(2.0, 6.0) if p.rng.random() < 0.5 else None)
            if p.rng.random() < 0.5:
                p.pause(p.uniform(0.2, 1.5))


def _move_base_like(p, target):
    accel, w_accel = p.uniform(0.3, 0.6), p.uniform(1.0, 3.0)
    v_max, w_max = p.uniform(0.2, 0.5), p.uniform(0.5, 1.0)
    p.turn(p.sign() * math.pi, w_max, accel=w_accel)
    while p.length < target:
        p.straight(v_max, p.uniform(1.0, 8.0), accel=accel)
        p.stop(accel=accel)
        if p.length < target:
            p.turn(p.sign() * math.radians(p.rng.choice((45.0, 90.0))), w_max, accel=w_accel)
    p.turn(p.sign() * p.uniform(math.radians(20), math.pi), w_max, accel=w_accel)


#: category -> (length range m, generator)
CATEGORIES = {
    'indoor_mixed': ((5.0, 40.0), _indoor_mixed),
    'fast_long': ((40.0, 150.0), _fast_long),
    'creeping': ((1.0, 6.0), _creeping),
    'reversing': ((2.0, 20.0), _reversing),
    'turns_in_place': ((2.0, 20.0), _turns_in_place),
    'move_base_like': ((5.0, 50.0), _move_base_like),
}


# --- paths that come back: plans that close exactly (whole ticks) ----------------------
def _ticks(duration):
    return max(1, int(round(duration / STEP)))


def _plan_straight(p, v, length):
    """``length`` m at about ``v`` m/s (sign: direction), exactly."""
    duration = _ticks(length / abs(v)) * STEP
    p.hold(math.copysign(length / duration, v), 0.0, duration)


def _plan_arc(p, v, radius, angle):
    """An arc of ``radius`` m turning by ``angle`` rad at about ``v`` m/s, exactly."""
    duration = _ticks(abs(angle) * radius / abs(v)) * STEP
    p.hold(math.copysign(abs(angle) * radius / duration, v), angle / duration, duration)


def _plan_turn(p, angle, rate):
    """A turn in place by ``angle`` rad at about ``rate`` rad/s, exactly."""
    duration = _ticks(abs(angle) / rate) * STEP
    p.hold(0.0, angle / duration, duration)


def _plan_corner(p, v, angle, rate, rounded):
    """Turn by ``angle``: in place, or (``rounded``: a radius, m) on an arc whose
    ends the caller's legs lose (``rounded`` each)."""
    if rounded:
        _plan_arc(p, v, rounded, angle)
    else:
        _plan_turn(p, angle, rate)


def _style(p):
    """(speed m/s, turn rate rad/s, corner radius m or 0) of one path."""
    return p.uniform(0.1, 0.35), p.uniform(0.4, 1.2), p.uniform(0.2, 0.5) if p.rng.random() < 0.4 else 0.0


def _figure_eight(p, target):
    v = p.uniform(0.1, 0.35)
    side = p.sign()
    _plan_straight(p, v, p.uniform(0.5, 3.0))
    while True:
        if p.rng.random() < 0.5:       # two circles touching where the path passes three times
            for turn in (side, -side):
                _plan_arc(p, v, p.uniform(0.5, 1.5), turn * 2.0 * math.pi)
        else:                           # teardrops crossing at right angles: legs = radius
            radius = p.uniform(0.4, 1.2)
            _plan_turn(p, side * math.pi / 4.0, p.uniform(0.4, 1.2))
            for turn in (-side, side):
                _plan_straight(p, v, radius)
                _plan_arc(p, v, radius, turn * 1.5 * math.pi)
                _plan_straight(p, v, radius)
            _plan_turn(p, -side * math.pi / 4.0, p.uniform(0.4, 1.2))
        if p.length >= target - 3.0 or p.rng.random() < 0.5:
            break
        if p.rng.random() < 0.3:
            p.pause(p.uniform(0.5, 2.0))
    _plan_straight(p, v, p.uniform(0.5, 3.0))


def _plan_rectangle(p, v, along, across, side, rate, rounded):
    """Round a rectangle (``along`` m the way the robot faces, ``across`` m to the
    ``side``) from the middle of a side, back to the same pose."""
    for index, leg in enumerate((along / 2.0, across, along, across)):
        _plan_straight(p, v, leg - (rounded if index == 0 else 2.0 * rounded))
        _plan_corner(p, v, side * math.pi / 2.0, rate, rounded)
    _plan_straight(p, v, along / 2.0 - rounded)


def _side_room(p, target):
    v, rate, rounded = _style(p)
    side = p.sign()
    while True:
        _plan_straight(p, v, p.uniform(1.0, 4.0) - rounded)
        _plan_corner(p, v, side * math.pi / 2.0, rate, rounded)
        door = p.uniform(0.8, 2.5)
        _plan_straight(p, v, door - rounded)
        _plan_rectangle(p, v, p.uniform(1.0, 3.0), p.uniform(1.0, 3.0), p.sign(), rate, rounded)
        _plan_turn(p, math.pi, rate)    # and out the way it came
        _plan_straight(p, v, door)
        _plan_turn(p, side * math.pi / 2.0, rate)
        if p.length >= target - 4.0 or p.rng.random() < 0.5:
            break
    _plan_straight(p, v, p.uniform(1.0, 4.0))


def _patrol(p, target):
    v, rate, rounded = _style(p)
    width, height = p.uniform(1.0, 4.0), p.uniform(1.0, 4.0)
    side = p.sign()
    for _ in range(max(1, min(3, int(target // (2.0 * (width + height)))))):
        _plan_rectangle(p, v, width, height, side, rate, rounded)   # past the start again
        if p.rng.random() < 0.3:
            p.pause(p.uniform(0.5, 3.0))
    _plan_straight(p, v, p.uniform(0.5, 2.0))
    _plan_turn(p, -side * math.pi / 2.0, rate)
    _plan_straight(p, v, p.uniform(1.0, 3.0))


def _dead_end(p, target):
    v, rate, _ = _style(p)
    for _ in range(p.rng.randint(1, 3)):
        _plan_straight(p, v, p.uniform(1.0, 3.0))
        side = p.sign()
        _plan_turn(p, side * math.pi / 2.0, rate)
        depth = p.uniform(1.0, 4.0)
        _plan_straight(p, v, depth)                     # into the dead end
        p.pause(p.uniform(0.5, 2.0))
        _plan_straight(p, -p.uniform(0.08, 0.2), depth)  # backed out the way it came
        _plan_turn(p, -side * math.pi / 2.0, rate)
        if p.length >= target:
            break
    _plan_straight(p, v, p.uniform(1.0, 3.0))


#: Paths that come back to where they have been: category -> (length range m, generator).
LOOP_CATEGORIES = {
    'figure_eight': ((6.0, 30.0), _figure_eight),
    'side_room': ((6.0, 40.0), _side_room),
    'patrol': ((5.0, 50.0), _patrol),
    'dead_end': ((4.0, 30.0), _dead_end),
}


def random_mission(category, seed):
    """The mission of ``category`` (:data:`CATEGORIES` or :data:`LOOP_CATEGORIES`)
    for ``seed`` (see module docstring)."""
    known = dict(CATEGORIES, **LOOP_CATEGORIES)
    if category not in known:
        raise ValueError('unknown path category %r (known: %s)' % (category, ', '.join(sorted(known))))
    (low, high), generate = known[category]
    rng = random.Random('%s:%d' % (category, seed))
    path = _Path(rng)
    generate(path, rng.uniform(low, high))
    path.pause(0.5)
    series = TrackedSeries if category in LOOP_CATEGORIES else CommandSeries
    return series(path.pieces, RATE, '%s_%d' % (category, seed),
                  'random %s path, seed %d' % (category, seed))

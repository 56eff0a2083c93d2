"""The model of one recording period, from landmark ``a`` to the next, ``b``: the speed and
heading over ``b.T`` s from all five variables at both ends, scaled to the recorded ``d``
(:func:`period_shape`), and the turn (:func:`period_turn`); docs/back_travel.md, "The route"."""
import math

from .geometry import wrap_angle
from .motion_events import EVENT_DEFAULTS

#: A modelled chord this many times longer or shorter than d is not trusted for its shape.
SHAPE_TRUST = 3.0
#: m/s; an end slower reads no direction: core/motion_events' still level.
STILL_SPEED = EVENT_DEFAULTS['event_speed'] * EVENT_DEFAULTS['event_hysteresis']
#: s; the odometry's step (kobuki_node, 50 Hz): a state's v is its speed over the step before it.
ODOMETRY_STEP = 0.02
#: m/s; an end no faster reads a reversal just past its crossing (one ODOMETRY_STEP at up to
#: 2 m/s^2 beyond event_speed: a motion event's sample).
REVERSAL_READ = EVENT_DEFAULTS['event_speed'] + 2.0 * ODOMETRY_STEP


def period_turn(previous, landmark):
    """Heading change (rad) from landmark ``previous`` to ``landmark``: the branch of
    wrap(psi - psi_previous) + 2 pi m nearest what the mean of the two turn rates gives."""
    change = wrap_angle(landmark.psi - previous.psi)
    expected = (previous.w + landmark.w) / 2.0 * landmark.T
    return change + 2.0 * math.pi * round((expected - change) / (2.0 * math.pi))


def _velocity_model(v_a, v_b, d, period):
    """Signed speed over the period as (v_a, v_b, bump): u(t) = v_a + (v_b - v_a) t
    + bump 6 t (1 - t), t in [0, 1]; the bump makes up a mean speed d / T the ends do
    not reach, in the direction of the motion (docs/back_travel.md, "The route")."""
    sign = v_a + v_b
    if v_a * v_b < 0.0:
        if abs(v_a) < STILL_SPEED or period <= 1.5 * ODOMETRY_STEP:
            sign = v_b
        else:
            sign = v_a
            v_b = 0.0 if STILL_SPEED <= abs(v_b) <= REVERSAL_READ else v_b
    mean = (abs(v_a) + abs(v_b)) / 2.0
    missing = d / period - mean
    if missing <= 0.0:
        return v_a, v_b, 0.0
    return v_a, v_b, math.copysign(missing, sign if sign != 0.0 else 1.0)


def period_shape(a, b, d, subdivisions):
    """Modelled motion from landmark state ``a`` to ``b`` (``b.T`` s): the chord
    direction (rad), intermediate points as offsets from the period's start
    scaled to ``d`` (or [] when the model is not trusted for the shape), the
    modelled speed at each point (start, intermediate..., end) and the turn."""
    period = b.T
    turn = period_turn(a, b)
    v_a, v_b, bump = _velocity_model(a.v, b.v, d, period)
    steps = max(2, subdivisions)
    grid = [k / float(steps) for k in range(steps + 1)]

    def velocity(t):
        t2, t3 = t * t, t * t * t
        heading = (a.psi + period * a.w * (t3 - 2.0 * t2 + t) + turn * (3.0 * t2 - 2.0 * t3)
                   + period * b.w * (t3 - t2))
        speed = v_a + (v_b - v_a) * t + bump * 6.0 * t * (1.0 - t)
        return speed * math.cos(heading), speed * math.sin(heading), speed, heading

    points, speeds = [], [abs(velocity(0.0)[2])]
    x = y = 0.0
    heading_sum_x = heading_sum_y = 0.0
    previous = velocity(0.0)
    for t0, t1 in zip(grid, grid[1:]):
        middle, end = velocity((t0 + t1) / 2.0), velocity(t1)
        h = period * (t1 - t0)
        x += h * (previous[0] + 4.0 * middle[0] + end[0]) / 6.0
        y += h * (previous[1] + 4.0 * middle[1] + end[1]) / 6.0
        heading_sum_x += math.cos(middle[3]) * (t1 - t0)
        heading_sum_y += math.sin(middle[3]) * (t1 - t0)
        points.append((x, y))
        speeds.append(abs(end[2]))
        previous = end
    modelled = math.hypot(x, y)
    if modelled > 1e-12:
        direction = math.atan2(y, x)
    else:   # no modelled motion: the mean heading, reversed if the motion was
        direction = math.atan2(heading_sum_y, heading_sum_x) + (math.pi if a.v + b.v < 0 else 0.0)
    points.pop()        # the end is the next landmark's point, placed exactly by d
    if d <= 0.0 or modelled <= 1e-12 or not 1.0 / SHAPE_TRUST <= d / modelled <= SHAPE_TRUST:
        return direction, [], [speeds[0], speeds[-1]], turn
    scale = d / modelled
    return direction, [(px * scale, py * scale) for px, py in points], speeds, turn

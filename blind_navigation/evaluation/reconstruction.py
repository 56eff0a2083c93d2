"""How well the landmarks describe the path: the path rebuilt from a recording's
landmarks (:func:`rebuild_path`, the points the closed-loop return's route runs
through, from core/route's chain) against the ground truth and against the odometry
it sampled, for the paper's adaptive two-rate sampling and for uniform sampling at
the same sample count (one period = recording time / adaptive sample count)."""
import numpy

from ..core.route import _chain
from ..sim.mission import load_mission
from .forward import harness_settings, record_forward


def rebuild_path(landmarks, anchor):
    """Landmark positions rebuilt from the landmarks, anchored at ``anchor`` (where
    recording stopped), in forward order: [(x, y)], start first."""
    landmarks = list(landmarks)
    chain = _chain(tuple(float(c) for c in anchor), landmarks, None)
    return [chain[-1][3] if chain else tuple(anchor)] + [link[0] for link in reversed(chain)]


def tick_times(landmarks):
    """Time of each landmark since recording started (the sum of the periods T)."""
    return list(numpy.cumsum([lm.T for lm in landmarks]))


def deviation(points, polyline):
    """Distance (m) from each of ``points`` to the polyline ``polyline``: numpy array."""
    p = numpy.asarray(points, dtype=float)[:, None, :]
    line = numpy.asarray(polyline, dtype=float)
    a, b = line[:-1][None, :, :], line[1:][None, :, :]
    ab = b - a
    length_sq = numpy.maximum((ab ** 2).sum(axis=2), 1e-12)
    t = numpy.clip(((p - a) * ab).sum(axis=2) / length_sq, 0.0, 1.0)
    closest = a + t[:, :, None] * ab
    return numpy.sqrt(((p - closest) ** 2).sum(axis=2)).min(axis=1)


def _summary(values):
    return float(numpy.mean(values)), float(numpy.max(values))


def compare_sampling(mission, profile='paper', seed=0, step=5, deadband=0.0):
    """Adaptive vs uniform sampling of the same run (same mission, profile, seed);
    the adaptive schedule's classifier dead-band is ``deadband`` (the paper's: 0).

    Returns {'adaptive'|'uniform': {'samples', 'period', 'truth_mean', 'truth_max',
    'odom_mean', 'odom_max'}}: mean and max distance (m) of every ``step``-th
    ground-truth / odometry pose of the forward run to the rebuilt path.
    """
    mission = load_mission(mission) if isinstance(mission, str) else mission
    defaults = harness_settings()
    adaptive = record_forward(mission, profile, seed, deadband=deadband)
    period = sum(lm.T for lm in adaptive.landmarks) / len(adaptive.landmarks)
    uniform = record_forward(mission, profile, seed, straight_period=period, curved_period=period)
    out = {}
    for name, record, straight in (('adaptive', adaptive, defaults['straight_period']),
                                   ('uniform', uniform, period)):
        rebuilt = rebuild_path(record.landmarks, record.anchor)
        truth = [(pose.x, pose.y) for _, pose in record.truth[::step]]
        odom = [(o.x, o.y) for o in record.odometry[::step]]
        truth_mean, truth_max = _summary(deviation(truth, rebuilt))
        odom_mean, odom_max = _summary(deviation(odom, rebuilt))
        out[name] = {'samples': len(record.landmarks), 'period': straight if name == 'uniform' else None,
                     'truth_mean': truth_mean, 'truth_max': truth_max,
                     'odom_mean': odom_mean, 'odom_max': odom_max}
    return out

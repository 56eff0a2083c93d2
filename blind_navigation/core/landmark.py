"""The paper's path landmark ``(v, w, d, T, psi)`` (equation 2: m/s, rad/s, m from the
previous landmark, s, rad) and its checks against core/plausibility.Limits."""
import math
from collections import namedtuple

from .plausibility import KOBUKI_MAX_V, KOBUKI_MAX_W, Limits

__all__ = ['FIELDS', 'KOBUKI_MAX_V', 'KOBUKI_MAX_W', 'Landmark', 'Limits', 'landmark_from_values']

FIELDS = ('v', 'w', 'd', 'T', 'psi')


class Landmark(namedtuple('Landmark', FIELDS)):
    """One path landmark; a tuple of five floats in REP 103 units."""

    __slots__ = ()

    def as_list(self):
        return [float(value) for value in self]


def landmark_from_values(values, limits=Limits()):
    """A Landmark from five numbers, or ValueError naming the bad field (not five numbers,
    NaN/Inf, ``d < 0``, ``T <= 0``, beyond ``limits``, ``|psi| > pi``)."""
    if not isinstance(values, (list, tuple)) or len(values) != len(FIELDS):
        raise ValueError('data must be a list of five numbers [v, w, d, T, psi], got %r' % (values,))
    numbers = []
    for name, value in zip(FIELDS, values):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError('%s is not a number: %r' % (name, value))
        if not math.isfinite(value):
            raise ValueError('%s is not finite: %r' % (name, value))
        numbers.append(float(value))
    landmark = Landmark(*numbers)
    if landmark.d < 0.0:
        raise ValueError('d is negative: %r' % landmark.d)
    if landmark.T <= 0.0:
        raise ValueError('T must be positive: %r' % landmark.T)
    problem = (limits.twist_problem(landmark.v, landmark.w)
               or limits.distance_problem(landmark.d, landmark.T))
    if problem:
        raise ValueError(problem)
    if abs(landmark.psi) > math.pi + 1e-6:
        raise ValueError('psi = %g is outside [-pi, pi]' % landmark.psi)
    return landmark

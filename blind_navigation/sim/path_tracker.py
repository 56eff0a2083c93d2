"""A planned path driven closed loop on ground truth, as a localised robot (or a person)
drives a route that revisits places, so that its loops really close.

:class:`TrackedSeries` is a command series whose pieces are the plan; its operator,
:class:`PathTracker`, follows the reference pose in time with Kanayama's tracking law
(ICRA 1990) on the true pose, stable for either sign of ``v_ref``; commands clamped to
the Kobuki's limits.
"""
import bisect
import math

from ..core.geometry import wrap_angle
from ..core.landmark import KOBUKI_MAX_V, KOBUKI_MAX_W
from .command_series import CommandSeries
from .kobuki import arc_motion

#: Tracking gains (see module docstring).
TRACKER_GAINS = {'k_x': 1.0, 'k_y': 10.0, 'k_yaw': 2.0}


class TrackedSeries(CommandSeries):
    """Command pieces driven as a plan by a :class:`PathTracker` (module docstring)."""

    def make_operator(self):
        return PathTracker(self)


class PathTracker(object):
    """The operator interface of sim/operator.Operator: ``start(pose)``,
    ``observe(t, pose)``, ``command(t)`` -> (v, w) or None once the plan is over."""

    def __init__(self, mission, gains=None):
        self.mission = mission
        self.gains = dict(TRACKER_GAINS, **(gains or {}))
        self._starts = None
        self._pose = None

    @property
    def started(self):
        return self._starts is not None

    def start(self, pose):
        """The plan starts now (t = 0) at the true ``pose``: the pose at each piece's start."""
        x, y, yaw = pose.x, pose.y, pose.yaw
        self._starts, self._times = [], []
        elapsed = 0.0
        for v, w, duration in self.mission.segments:
            self._starts.append((x, y, yaw))
            self._times.append(elapsed)
            x, y, yaw = arc_motion(x, y, yaw, v, w, duration)
            elapsed += duration
        self._end = (x, y, yaw)
        self._pose = pose

    def observe(self, t, pose):
        if self._starts is None:
            raise RuntimeError('PathTracker.observe before start')
        self._pose = pose

    def reference(self, t):
        """(x, y, yaw, v, w) of the plan at time ``t``."""
        index = max(0, bisect.bisect_right(self._times, t) - 1)
        v, w, duration = self.mission.segments[index]
        x, y, yaw = arc_motion(*self._starts[index], v, w, min(duration, t - self._times[index]))
        return x, y, yaw, v, w

    def command(self, t):
        if self._starts is None:
            raise RuntimeError('PathTracker.command before start')
        if t >= self.mission.duration - 1e-9:
            return None
        x_ref, y_ref, yaw_ref, v_ref, w_ref = self.reference(t)
        pose, g = self._pose, self.gains
        dx, dy = x_ref - pose.x, y_ref - pose.y
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        e_x, e_y = c * dx + s * dy, -s * dx + c * dy
        e_yaw = wrap_angle(yaw_ref - pose.yaw)
        v = v_ref * math.cos(e_yaw) + g['k_x'] * e_x
        w = w_ref + v_ref * g['k_y'] * e_y + g['k_yaw'] * math.sin(e_yaw)
        return (max(-KOBUKI_MAX_V, min(KOBUKI_MAX_V, v)), max(-KOBUKI_MAX_W, min(KOBUKI_MAX_W, w)))

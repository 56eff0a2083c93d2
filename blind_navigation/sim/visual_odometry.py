"""Drift model of the fake RTAB-Map visual odometry: the true pose plus errors that grow with motion.

Each update takes the true pose, and integrates the true motion increment with
a per-run distance scale error and a heading error that random-walks with the
distance travelled and the angle turned (visual odometry drifts while moving,
not while standing). All draws come from ``seed``.
"""
import math
import random

from ..core.geometry import Pose2D, wrap_angle

#: The fake TurtleBot's visual-odometry drift (fake_vision's defaults; the harness uses them too).
VO_DRIFT_DEFAULTS = {'scale_error_std': 0.01, 'yaw_drift_per_metre': 0.005,
                     'yaw_drift_per_radian': 0.005}
#: RTAB-Map's odometry rate on the fake TurtleBot, Hz.
VO_RATE = 30.0


class DriftingOdometry(object):
    """``scale_error_std`` (fraction), ``yaw_drift_per_metre`` and ``yaw_drift_per_radian``
    (rad std per sqrt(m) / sqrt(rad))."""

    def __init__(self, seed=0, scale_error_std=0.01, yaw_drift_per_metre=0.01, yaw_drift_per_radian=0.01):
        self._rng = random.Random(seed)
        self.scale = 1.0 + self._rng.gauss(0.0, scale_error_std)
        self.yaw_drift_per_metre = yaw_drift_per_metre
        self.yaw_drift_per_radian = yaw_drift_per_radian
        self._last_truth = None
        self.pose = Pose2D(0.0, 0.0, 0.0)
        self._yaw_error = 0.0

    def update(self, truth):
        """Advance to the true pose ``truth`` (Pose2D, world); returns the drifting estimate."""
        if self._last_truth is None:
            self._last_truth = truth
            self._origin_yaw = truth.yaw
            return self.pose
        last = self._last_truth
        dx, dy = truth.x - last.x, truth.y - last.y
        dist = math.hypot(dx, dy)
        turn = abs(wrap_angle(truth.yaw - last.yaw))
        sigma = math.sqrt(self.yaw_drift_per_metre ** 2 * dist + self.yaw_drift_per_radian ** 2 * turn)
        if sigma > 0:
            self._yaw_error += self._rng.gauss(0.0, sigma)
        # the true increment, seen from the start frame, rotated by the heading error and scaled
        heading = math.atan2(dy, dx) - self._origin_yaw + self._yaw_error
        x, y, _ = self.pose
        self.pose = Pose2D(x + self.scale * dist * math.cos(heading),
                           y + self.scale * dist * math.sin(heading),
                           wrap_angle(truth.yaw - self._origin_yaw + self._yaw_error))
        self._last_truth = truth
        return self.pose

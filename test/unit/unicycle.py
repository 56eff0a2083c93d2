"""Test helper: an exact unicycle (commands take effect at once, no noise) to
record paths with the real recorder and drive the back-travel controllers."""
import math

from blind_navigation.core.geometry import OdomState, wrap_angle
from blind_navigation.core.recorder import record_path
from blind_navigation.core.segment import SamplingSchedule

DT = 0.02


class Unicycle(object):
    """Planar pose integrated exactly over piecewise-constant (v, w)."""

    def __init__(self, x=0.0, y=0.0, yaw=0.0):
        self.x, self.y, self.yaw = x, y, yaw
        self.v = self.w = 0.0
        self.t = 0.0

    def move(self, v, w, dt):
        if abs(w) < 1e-12:
            self.x += v * dt * math.cos(self.yaw)
            self.y += v * dt * math.sin(self.yaw)
        else:
            radius = v / w
            new_yaw = self.yaw + w * dt
            self.x += radius * (math.sin(new_yaw) - math.sin(self.yaw))
            self.y -= radius * (math.cos(new_yaw) - math.cos(self.yaw))
            self.yaw = new_yaw
        self.yaw = wrap_angle(self.yaw)
        self.v, self.w = v, w
        self.t += dt

    @property
    def odom(self):
        return OdomState(self.x, self.y, self.yaw, self.v, self.w, self.t)


def drive(profile):
    """Positions over time for ``profile`` = [(v, w, seconds), ...]; returns
    (odom_at(t), duration) for :func:`record_path`."""
    duration = sum(seconds for _, _, seconds in profile)

    def odom_at(t):
        robot = Unicycle()
        left = t
        for v, w, seconds in profile:
            span = min(seconds, left)
            if span > 0:
                robot.move(v, w, span)
            robot.v, robot.w = v, w
            left -= span
            if left <= 1e-12:
                break
        robot.t = t
        return robot.odom
    return odom_at, duration


def record(profile, straight_period=2.0, curved_period=1.0):
    """Landmarks (recording order) and the end odometry of ``profile``."""
    odom_at, duration = drive(profile)
    ticks = record_path(odom_at, duration, SamplingSchedule(straight_period, curved_period))
    return [landmark for _, landmark in ticks], odom_at(duration)


def run_controllers(robot, controllers, dt=DT, limit=10000):
    """Run each controller to completion on ``robot``; the command of one cycle
    is applied for ``dt``. Returns the controllers."""
    for controller in controllers:
        controller.start(robot.odom)
        for _ in range(limit):
            v, w = controller.step(robot.odom)
            if controller.done or controller.failed:
                break
            robot.move(v, w, dt)
        assert controller.done, 'controller %r did not finish' % controller
    return controllers

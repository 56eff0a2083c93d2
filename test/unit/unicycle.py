"""Test helper: an exact unicycle (commands take effect at once, no noise) to
record paths with the real recorder and drive the back-travel controllers."""
import math

from blind_navigation.core.geometry import OdomState, wrap_angle
from blind_navigation.core.recorder import PathRecorder, record_path
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


def record(profile, straight_period=2.0, curved_period=1.0, events=False):
    """Landmarks (recording order) and the end odometry of ``profile``. With
    ``events``, also a landmark just before and just after each change of the
    way of moving (still, forward, backward; turning or not), as
    core/motion_events proposes (this unicycle changes its velocity at once, so
    one landmark each side keeps every period's motion uniform)."""
    odom_at, duration = drive(profile)
    if not events:
        ticks = record_path(odom_at, duration, SamplingSchedule(straight_period, curved_period))
        return [landmark for _, landmark in ticks], odom_at(duration)
    return _record_with_events(profile, odom_at, duration, straight_period, curved_period), \
        odom_at(duration)


def _motion_class(v, w):
    return (0 if v == 0 else math.copysign(1, v), w != 0)


def _record_with_events(profile, odom_at, duration, straight_period, curved_period):
    changes, elapsed = [], 0.0
    for (v0, w0, seconds), (v1, w1, _) in zip(profile, profile[1:]):
        elapsed += seconds
        if _motion_class(v0, w0) != _motion_class(v1, w1):
            changes += [elapsed - 1e-3, elapsed + 1e-3]
    schedule, recorder = SamplingSchedule(straight_period, curved_period), PathRecorder()
    start = odom_at(0.0)
    recorder.start(start)
    period = schedule.update(start.yaw)
    next_tick, last, landmarks = period, 0.0, []
    while True:
        t = min([next_tick] + changes[:1])
        if t > duration - 1e-9:
            break
        odom = odom_at(t)
        landmarks.append(recorder.take(odom, odom.yaw, t - last))
        last = t
        if changes and t == changes[0]:
            changes.pop(0)
        else:
            period = schedule.update(odom.yaw)
            next_tick = t + period
    if duration - last > 1e-9:
        odom = odom_at(duration)
        landmarks.append(recorder.take(odom, odom.yaw, duration - last))
    return landmarks


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

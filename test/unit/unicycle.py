"""Test helper: the simulated Kobuki (blind_navigation/sim/kobuki.py) with the
``ideal`` profile, an exact unicycle (commands take effect at once, no noise),
to record paths with the real recorder and drive the back-travel controllers;
and paths planned as pieces of constant (v, w), integrated with the same
kinematics (sim/kobuki.arc_motion)."""
import bisect
import math
from types import SimpleNamespace

from blind_navigation.core.route_follower import RouteFollower
from blind_navigation.core.geometry import OdomState, Pose2D, wrap_angle
from blind_navigation.core.recorder import PathRecorder
from blind_navigation.core.segment import SamplingSchedule
from blind_navigation.sim.kobuki import CMD_TIMEOUT, SimulatedKobuki, arc_motion, load_profile

DT = 0.02
IDEAL = load_profile('ideal')


class Unicycle(object):
    """A SimulatedKobuki with the ideal profile started at (x, y, yaw), read as an
    ideal odometry would report it: ``x``, ``y``, ``yaw`` (wrapped), ``v``, ``w``
    (its true pose and twist), ``t`` (s) and ``odom`` (OdomState)."""

    def __init__(self, x=0.0, y=0.0, yaw=0.0):
        self.base = SimulatedKobuki(IDEAL, start=Pose2D(x, y, yaw))

    def move(self, v, w, dt):
        """Command (v, w) (m/s, rad/s; clamped to the Kobuki's limits) and let ``dt``
        s pass (a multiple of the profile's physics step, at most the Kobuki's
        command timeout: a controller's cycle)."""
        if dt > CMD_TIMEOUT:
            raise ValueError('Unicycle.move: dt %r s is beyond the Kobuki\'s command timeout' % dt)
        self.base.command(v, w)
        self.base.step(dt)

    x = property(lambda self: self.base.true_pose.x)
    y = property(lambda self: self.base.true_pose.y)
    yaw = property(lambda self: wrap_angle(self.base.true_pose.yaw))
    v = property(lambda self: self.base.true_twist[0])
    w = property(lambda self: self.base.true_twist[1])
    t = property(lambda self: self.base.t)

    @property
    def odom(self):
        return OdomState(self.x, self.y, self.yaw, self.v, self.w, self.t)


def drive(profile):
    """The planned path of ``profile`` = [(v, w, seconds), ...] from the origin,
    exact; returns (odom_at(t), duration) for :func:`record_path`. At a piece's
    end, (v, w) is that piece's (the velocity the period ending there had)."""
    ends, starts, pose, elapsed = [], [], (0.0, 0.0, 0.0), 0.0
    for v, w, seconds in profile:
        starts.append((elapsed, pose))
        x, y, yaw = arc_motion(pose[0], pose[1], pose[2], v, w, seconds)
        pose, elapsed = (x, y, wrap_angle(yaw)), elapsed + seconds
        ends.append(elapsed + 1e-12)
    duration = elapsed

    def odom_at(t):
        index = min(bisect.bisect_left(ends, t), len(profile) - 1)
        v, w, seconds = profile[index]
        start, (x, y, yaw) = starts[index]
        x, y, yaw = arc_motion(x, y, yaw, v, w, max(0.0, min(seconds, t - start)))
        return OdomState(x, y, wrap_angle(yaw), v, w, t)
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


def follow_route(route, start, dt=DT, limit=100000, section=0):
    """A core/route_follower.RouteFollower (``stop_lead`` 0: this unicycle stops at once)
    driving ``route`` from goal ``section`` on a Unicycle put at ``start`` (x, y, yaw),
    stepped every ``dt`` s until done or failed, at most ``limit`` steps.
    Returns (robot, follower)."""
    robot = Unicycle(*start)
    follower = RouteFollower(route, SimpleNamespace(stop_lead=0.0))
    follower.start(robot.odom, section=section)
    for _ in range(limit):
        v, w = follower.step(robot.odom)
        if follower.done or follower.failed:
            break
        robot.move(v, w, dt)
    return robot, follower


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


def record_path(odom_at, duration, schedule, recorder=None):
    """Plain-Python run of the sampling publisher and saver over a known path.

    ``odom_at(t)`` gives the OdomState ``t`` s after recording started;
    ``schedule`` is a :class:`~.segment.SamplingSchedule`. As in the nodes,
    the start yaw is the schedule's first yaw, each tick feeds the schedule
    its yaw, the next period comes from the schedule, and at ``duration``
    (vision lost) a final landmark covers the partial cycle since the last
    tick. Returns ``[(tick time, Landmark), ...]``.
    """
    recorder = recorder or PathRecorder()
    start = odom_at(0.0)
    recorder.start(start)
    period = schedule.update(start.yaw)
    t, ticks = 0.0, []
    while t + period <= duration + 1e-9:
        t += period
        odom = odom_at(t)
        ticks.append((t, recorder.take(odom, odom.yaw, period)))
        period = schedule.update(odom.yaw)
    if duration - t > 1e-9:
        odom = odom_at(duration)
        ticks.append((duration, recorder.take(odom, odom.yaw, duration - t)))
    return ticks

"""A scripted planar path for the recording tests: segments of constant (v, w),
integrated exactly (the simulated Kobuki's unicycle kinematics,
sim/kobuki.arc_motion), so tests know the true pose at any time.

Shared by test/unit/test_recorder.py and the recording rostests' odometry
publisher (test/rostest/test_recording_scripted.py).
"""
from blind_navigation.core.geometry import OdomState, wrap_angle
from blind_navigation.sim.kobuki import arc_motion

#: The paper's set velocities (section 5.1): LSV 0.086 m/s, ASV 0.097 rad/s.
LSV = 0.086
ASV = 0.097
#: Straight 12 s, a left arc of 16 s (~89 deg), straight 12 s.
STRAIGHT_ARC_STRAIGHT = ((12.0, LSV, 0.0), (16.0, LSV, ASV), (12.0, LSV, 0.0))


class ScriptedPath(object):
    """Pose and twist along ``segments`` = ((duration s, v m/s, w rad/s), ...)."""

    def __init__(self, segments=STRAIGHT_ARC_STRAIGHT, x=0.0, y=0.0, yaw=0.0):
        if not segments:
            raise ValueError('ScriptedPath needs at least one segment')
        self.segments = [tuple(float(v) for v in segment) for segment in segments]
        self.starts = []            # (t0, x0, y0, yaw0) of each segment
        t = 0.0
        for duration, v, w in self.segments:
            self.starts.append((t, x, y, yaw))
            x, y, yaw = arc_motion(x, y, yaw, v, w, duration)
            t += duration
        self.duration = t

    def segment_at(self, t):
        """Index of the segment in force at time ``t`` (the last one after the end)."""
        for index in range(len(self.segments) - 1, -1, -1):
            if t >= self.starts[index][0]:
                return index
        return 0

    def state(self, t):
        """OdomState at ``t`` s (yaw unwrapped internally, reported wrapped);
        the robot stands still after the end."""
        t = max(0.0, t)
        index = self.segment_at(t)
        t0, x, y, yaw = self.starts[index]
        duration, v, w = self.segments[index]
        dt = min(t - t0, duration)
        x, y, yaw = arc_motion(x, y, yaw, v, w, dt)
        if t > self.duration:
            v = w = 0.0
        return OdomState(x, y, wrap_angle(yaw), v, w, t)

    def length(self, t0=0.0, t1=None):
        """Arc length travelled between t0 and t1, m."""
        t1 = self.duration if t1 is None else t1
        total = 0.0
        for (start, _, _, _), (duration, v, _) in zip(self.starts, self.segments):
            overlap = min(t1, start + duration) - max(t0, start)
            total += abs(v) * max(0.0, overlap)
        return total

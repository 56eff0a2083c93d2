"""Trajectories in TUM format (``timestamp x y z qx qy qz qw``, one pose a line),
readable by `evo` (evo_traj tum ..., evo_ape tum ground_truth.tum other.tum)."""
import os

from ..core.geometry import quaternion_from_yaw


def tum_lines(poses):
    """Lines for ``poses`` = [(t, x, y, yaw)]."""
    lines = []
    for t, x, y, yaw in poses:
        qx, qy, qz, qw = quaternion_from_yaw(yaw)
        lines.append('%.4f %.6f %.6f 0.0 %.6f %.6f %.6f %.6f\n' % (t, x, y, qx, qy, qz, qw))
    return lines


def write_tum(path, poses):
    """Write [(t, x, y, yaw)] to ``path`` in TUM format; returns the path."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, 'w') as stream:
        stream.writelines(tum_lines(poses))
    return path


def read_tum(path):
    """[(t, x, y, z, qx, qy, qz, qw)] from a TUM file (comments '#' skipped)."""
    poses = []
    with open(path) as stream:
        for number, line in enumerate(stream, 1):
            if not line.strip() or line.startswith('#'):
                continue
            fields = line.split()
            if len(fields) != 8:
                raise ValueError('%s:%d: a TUM line has 8 fields, got %d' % (path, number, len(fields)))
            poses.append(tuple(float(f) for f in fields))
    return poses


def forward_trajectories(forward, rebuilt):
    """TUM pose lists of one ForwardRecord: ground truth and wheel odometry at
    every control step, and the path rebuilt from the landmarks (at the tick
    times, heading = the landmark's psi; the start at t = 0, heading 0)."""
    truth = [(t, p.x, p.y, p.yaw) for t, p in forward.truth]
    odom = [(t, o.x, o.y, o.yaw) for (t, _), o in zip(forward.truth, forward.odometry)]
    times, yaws, elapsed = [0.0], [0.0], 0.0
    for landmark in forward.landmarks:
        elapsed += landmark.T
        times.append(elapsed)
        yaws.append(landmark.psi)
    landmarks = [(t, x, y, yaw) for t, (x, y), yaw in zip(times, rebuilt, yaws)]
    return {'ground_truth': truth, 'odometry': odom, 'landmarks': landmarks}

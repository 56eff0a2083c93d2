"""Planar geometry helpers (REP 103: metres, radians, counter-clockwise positive)."""
import math
from collections import namedtuple

Pose2D = namedtuple('Pose2D', 'x y yaw')
Pose2D.__doc__ = 'A planar pose: position in metres, yaw in radians.'


def wrap_angle(angle):
    """Return ``angle`` wrapped into [-pi, pi)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def yaw_from_quaternion(x, y, z, w):
    """Yaw of a quaternion (as tf's euler_from_quaternion); ValueError for a null or
    non-finite one (RTAB-Map's "lost")."""
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if not math.isfinite(norm) or norm < 1e-9:
        raise ValueError('invalid quaternion (%g, %g, %g, %g)' % (x, y, z, w))
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quaternion_from_yaw(yaw):
    """Quaternion (x, y, z, w) of a pure rotation by ``yaw`` about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def distance(ax, ay, bx, by):
    """Euclidean distance between points (ax, ay) and (bx, by)."""
    return math.hypot(bx - ax, by - ay)


OdomState = namedtuple('OdomState', 'x y yaw v w stamp')
OdomState.__doc__ = ('What the layer reads from odometry: pose (m, rad), twist.linear.x (m/s), '
                     'twist.angular.z (rad/s) and the stamp (s, sim time).')

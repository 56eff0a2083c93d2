"""The fields the layer uses of a serialised nav_msgs/Odometry, read with one ``struct``
call (after the two strings, pose, twist and covariances are 85 fixed float64)."""
import struct
from collections import namedtuple

from .geometry import OdomState, yaw_from_quaternion

_U32 = struct.Struct('<I')
_STAMP = struct.Struct('<II')
_DIAGONAL = 'd48x' * 5 + 'd'           # 36 float64, keeping indices 0, 7, ..., 35
_TAIL = struct.Struct('<2d8x4d' + _DIAGONAL + 'd32xd' + _DIAGONAL)
FIXED_SIZE = 680

WireOdometry = namedtuple('WireOdometry', 'stamp frame_id x y qx qy qz qw pose_covariance v w '
                                          'twist_covariance')
WireOdometry.__doc__ = ('stamp (s), frame_id, x, y (m), quaternion, pose covariance diagonal, '
                        'v (m/s), w (rad/s), twist covariance diagonal.')


def read_odometry(buff):
    """The :class:`WireOdometry` of ``buff`` (bytes); ValueError when it is too short."""
    size = len(buff)
    if size < 20 + FIXED_SIZE:
        raise ValueError('%d bytes are too few for a nav_msgs/Odometry' % size)
    secs, nsecs = _STAMP.unpack_from(buff, 4)
    (frame_length,) = _U32.unpack_from(buff, 12)
    child_at = 16 + frame_length
    if child_at + 4 > size:
        raise ValueError('frame_id of %d bytes runs past the %d-byte message' % (frame_length, size))
    (child_length,) = _U32.unpack_from(buff, child_at)
    pose_at = child_at + 4 + child_length
    if pose_at + FIXED_SIZE > size:
        raise ValueError('the message needs %d bytes, it has %d' % (pose_at + FIXED_SIZE, size))
    values = _TAIL.unpack_from(buff, pose_at)
    frame_id = bytes(buff[16:child_at]).decode('utf-8', 'replace')
    return WireOdometry(secs + nsecs * 1e-9, frame_id, values[0], values[1], values[2], values[3],
                        values[4], values[5], values[6:12], values[12], values[13], values[14:20])


def odom_state(wire):
    """OdomState of a :class:`WireOdometry`; ValueError for a non-finite pose or twist or a
    null quaternion (RTAB-Map's "lost")."""
    values = (wire.x, wire.y, wire.v, wire.w)
    if not all(value == value and abs(value) != float('inf') for value in values):
        raise ValueError('non-finite odometry (x, y, v, w) = %r' % (values,))
    yaw = yaw_from_quaternion(wire.qx, wire.qy, wire.qz, wire.qw)
    return OdomState(wire.x, wire.y, yaw, wire.v, wire.w, wire.stamp)

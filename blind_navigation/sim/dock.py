"""The Kobuki's charging dock in the fake's world: its IR fields and its charging contacts.

Plain Python. :class:`Dock` turns the robot's true pose into the three dock IR
receivers' bytes (``data[0]`` right, ``[1]`` central, ``[2]`` left, as kobuki_msgs/
DockInfraRed and kobuki_dock_drive read them) and into the charger and bumper the
dock causes. Geometry and sources: docs/fake_turtlebot.md (The dock).
"""
import math
from collections import namedtuple

from ..core.geometry import Pose2D, wrap_angle
from .arena import ROBOT_RADIUS

NEAR_LEFT, NEAR_CENTER, NEAR_RIGHT, FAR_CENTER, FAR_LEFT, FAR_RIGHT = 1, 2, 4, 8, 16, 32
NEAR, FAR = NEAR_LEFT | NEAR_CENTER | NEAR_RIGHT, FAR_CENTER | FAR_LEFT | FAR_RIGHT
FIELD_HALF_WIDTH = 1.0        # m each side of the dock's axis: the field is ~2 m x 5 m (issue 31)
FAR_RANGE = 5.0               # m ahead of the dock
NEAR_RANGE = 2.5              # m: the near field half as deep as the far (Kobuki's dock_ir_fields figure)
CENTRAL_HALF_WIDTH = 0.05     # m: the central region is a narrow strip on the axis (same figure)
BORDER_OVERLAP = 0.02         # m: left/right regions reach this far into the central one (overlap at borders)
#: robot-side receivers: (name, axis from the heading), data[0..2] order; each sees +-RECEIVER_HALF_FOV
RECEIVERS = (('right', -math.radians(60.0)), ('center', 0.0), ('left', math.radians(60.0)))
RECEIVER_HALF_FOV = math.radians(30.0)   # the three together cover the front half, no overlap
RECEIVER_RADIUS = 0.15        # m from the robot's centre (behind the front bumper)
CONTACT_HALF_WIDTH = 0.05     # m: the charging contacts meet when the robot's centre is this near the axis
CONTACT_YAW = math.radians(20.0)  # and the robot faces the dock within this
DOCK_HALF_WIDTH = 0.15        # m: the dock's body; meeting it elsewhere presses the bumper
UNDOCK_BACKOFF = 0.15         # m backed off the dock before the mission (docs: TurtleBot 4's undock)
CHARGING, CHARGED, DISCHARGING = 6, 2, 0     # kobuki_msgs/SensorState charger values
BATTERY_FULL = 16.5           # V, kobuki_node's battery_capacity: charged at or above it
BUMPER_CENTRE = 2             # kobuki_msgs/SensorState bumper bit

DockContact = namedtuple('DockContact', 'docked bumper')
DockContact.__doc__ = 'docked: on the charging contacts; bumper: SensorState bumper bits the dock presses.'


def regions(u, v):
    """Region bits at dock-frame point (u ahead of the dock's face, v to the dock's left)."""
    if not 0.0 < u <= FAR_RANGE or abs(v) > FIELD_HALF_WIDTH:
        return 0
    near = u <= NEAR_RANGE
    bits = 0
    if abs(v) <= CENTRAL_HALF_WIDTH:
        bits |= FAR_CENTER | (NEAR_CENTER if near else 0)
    if v >= CENTRAL_HALF_WIDTH - BORDER_OVERLAP:
        bits |= FAR_LEFT | (NEAR_LEFT if near else 0)
    if v <= -(CENTRAL_HALF_WIDTH - BORDER_OVERLAP):
        bits |= FAR_RIGHT | (NEAR_RIGHT if near else 0)
    return bits


class Dock(object):
    """A dock whose face centre is at ``pose`` (Pose2D, world), its beams along ``pose.yaw``."""

    def __init__(self, pose):
        self.pose = Pose2D(*pose)

    @classmethod
    def behind(cls, start, backoff=UNDOCK_BACKOFF):
        """The dock a robot at ``start`` has backed ``backoff`` m off and turned away from:
        on the robot's axis behind it, its beams along the robot's heading."""
        gap = ROBOT_RADIUS + backoff
        return cls(Pose2D(start.x - gap * math.cos(start.yaw), start.y - gap * math.sin(start.yaw),
                          start.yaw))

    def to_dock(self, x, y):
        """(u, v) of world point (x, y) in the dock's frame."""
        dx, dy = x - self.pose.x, y - self.pose.y
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        return c * dx + s * dy, -s * dx + c * dy

    def docked_pose(self):
        """The robot's pose on the charging contacts."""
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        return Pose2D(self.pose.x + ROBOT_RADIUS * c, self.pose.y + ROBOT_RADIUS * s,
                      wrap_angle(self.pose.yaw + math.pi))

    def ir(self, robot):
        """[right, central, left] receiver bytes for the robot at ``robot`` (Pose2D, world): the
        regions at each receiver, where the dock (seen from the robot's centre) is in its view."""
        data, bearing = [], math.atan2(self.pose.y - robot.y, self.pose.x - robot.x)
        for _, axis in RECEIVERS:
            heading = robot.yaw + axis
            rx, ry = robot.x + RECEIVER_RADIUS * math.cos(heading), robot.y + RECEIVER_RADIUS * math.sin(heading)
            seen = abs(wrap_angle(bearing - heading)) <= RECEIVER_HALF_FOV
            data.append(regions(*self.to_dock(rx, ry)) if seen else 0)
        return data

    def contact(self, robot):
        """DockContact for the robot at ``robot``: its front at the dock's face, on the axis and
        facing it is docked; at the face elsewhere on the dock's body the bumper is pressed."""
        front_u, front_v = self.to_dock(robot.x + ROBOT_RADIUS * math.cos(robot.yaw),
                                        robot.y + ROBOT_RADIUS * math.sin(robot.yaw))
        if front_u > 0.005 or front_u < -0.1 or abs(front_v) > DOCK_HALF_WIDTH:
            return DockContact(False, 0)
        _, centre_v = self.to_dock(robot.x, robot.y)
        facing = abs(wrap_angle(robot.yaw - self.pose.yaw - math.pi)) <= CONTACT_YAW
        if facing and abs(centre_v) <= CONTACT_HALF_WIDTH:
            return DockContact(True, 0)
        return DockContact(False, BUMPER_CENTRE)


def charger_state(docked, battery):
    """SensorState ``charger``: charging on the dock until the battery (V) is full, then charged."""
    if not docked:
        return DISCHARGING
    return CHARGED if battery >= BATTERY_FULL else CHARGING


def dock_from_spec(spec, start=Pose2D(0.0, 0.0, 0.0)):
    """The dock a launch arg names: ``none`` or '' (no dock), ``start`` (:meth:`Dock.behind` the
    robot's start) or ``x y yaw`` (its face centre in the world, m and rad); ValueError else."""
    spec = str(spec).strip()
    if spec in ('', 'none'):
        return None
    if spec == 'start':
        return Dock.behind(start)
    try:
        x, y, yaw = (float(part) for part in spec.replace(',', ' ').split())
    except ValueError:
        raise ValueError('dock must be none, start or "x y yaw" (m, m, rad), got %r' % spec)
    if not all(math.isfinite(value) for value in (x, y, yaw)):
        raise ValueError('dock pose must be finite, got %r' % spec)
    return Dock(Pose2D(x, y, yaw))


def bumper_bits(contacts):
    """SensorState ``bumper`` bits of sim/arena Contacts (None: no arena)."""
    bits = {'right': 1, 'center': BUMPER_CENTRE, 'left': 4}
    return sum(bits[name] for name in contacts.bumper) if contacts else 0
